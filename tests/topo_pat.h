/* topo_pat.h - crease patterns built in C for the topology tests
 * (test_topology.c, test_topology_errors.c), without the study parser:
 * a study with room for MAXV vertices and MAXF folds, and the reference
 * patterns of CASES.md. */
#ifndef SF_TEST_TOPO_PAT_H
#define SF_TEST_TOPO_PAT_H

#include "topology.h"

#define MAXV 64
#define MAXF 64

typedef struct pat {
    sf_study s;
    sf_vertex v[MAXV];
    sf_fold_def f[MAXF];
    int outline[MAXV];
    sf_material mat;
    double width, setback[2];   /* defaults for pat_fold() */
} pat;

pat *pat_new(const char *path);
int pat_find(const pat *P, const char *name);
void pat_vertex(pat *P, const char *name, double x, double y);
void pat_move(pat *P, const char *name, double x, double y);
void pat_outline(pat *P, const char *names);
void pat_fold(pat *P, const char *a, const char *b, double da, double db);
void pat_fixed(pat *P, double x, double y);
pat *make_strip3(int cw);
pat *make_waterbomb2(void);
/* square4 variants (studies/square4*.cfg) */
enum { SQ_PLAIN, SQ_NARROW, SQ_CORNER, SQ_IRREGULAR };
pat *make_square4(int variant);
pat *make_fold1(void);
void build_ok(pat *P, sf_topology *t);

#endif
