/* tsv_test.h - the tests' one reader of the TSV files `smoothfold run`
 * writes (branch.tsv, special.tsv, ...), by column name, and the run
 * itself.  Include after cmocka.h.  The program and the studies are found
 * through $SF_BUILDDIR and $SF_SRCDIR (set by `make check`). */
#ifndef SF_TSV_TEST_H
#define SF_TSV_TEST_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef SF_SRCDIR
#define SF_SRCDIR "."
#endif

typedef struct tsv {
    int ncol, nrow;
    char **name;
    char ***cell;     /* [row][col] strings ("" for an empty field) */
    char *header;     /* the # comment lines, each ending in '\n' */
} tsv;

static inline void tsv_read(tsv *t, const char *path)
{
    memset(t, 0, sizeof *t);
    FILE *f = fopen(path, "r");
    if (!f) print_error("cannot open %s\n", path);
    assert_non_null(f);
    char line[1 << 16];
    int cap = 0;
    size_t nh = 0;
    t->header = calloc(1, 1);
    assert_non_null(t->header);
    while (fgets(line, sizeof line, f)) {
        size_t L = strlen(line);
        while (L && (line[L - 1] == '\n' || line[L - 1] == '\r')) line[--L] = '\0';
        if (line[0] == '#') {
            t->header = realloc(t->header, nh + L + 2);
            assert_non_null(t->header);
            memcpy(t->header + nh, line, L);
            nh += L;
            t->header[nh++] = '\n';
            t->header[nh] = '\0';
            continue;
        }
        if (L == 0) continue; /* block separator */
        char **fields = NULL;
        int nf = 0;
        char *p = line;
        for (;;) {
            char *tab = strchr(p, '\t');
            if (tab) *tab = '\0';
            fields = realloc(fields, sizeof(char *) * (size_t)(nf + 1));
            assert_non_null(fields);
            fields[nf++] = strdup(p);
            if (!tab) break;
            p = tab + 1;
        }
        if (!t->name) {
            t->name = fields;
            t->ncol = nf;
            continue;
        }
        assert_int_equal(nf, t->ncol);
        if (t->nrow == cap) {
            cap = cap ? 2 * cap : 64;
            t->cell = realloc(t->cell, sizeof(char **) * (size_t)cap);
            assert_non_null(t->cell);
        }
        t->cell[t->nrow++] = fields;
    }
    fclose(f);
    assert_non_null(t->name);
}

static inline int tsv_col(const tsv *t, const char *name)
{
    for (int i = 0; i < t->ncol; i++)
        if (strcmp(t->name[i], name) == 0) return i;
    print_error("no column %s\n", name);
    fail();
    return -1;
}

static inline double tsv_num(const tsv *t, int row, const char *name)
{
    const char *s = t->cell[row][tsv_col(t, name)];
    char *end;
    double v = strtod(s, &end);
    if (end == s || *end) {
        print_error("row %d column %s: '%s' is not a number\n", row, name, s);
        fail();
    }
    return v;
}

static inline const char *tsv_str(const tsv *t, int row, const char *name)
{
    return t->cell[row][tsv_col(t, name)];
}

static inline void tsv_free(tsv *t)
{
    for (int r = 0; r < t->nrow; r++) {
        for (int c = 0; c < t->ncol; c++) free(t->cell[r][c]);
        free(t->cell[r]);
    }
    for (int c = 0; c < t->ncol; c++) free(t->name[c]);
    free(t->name);
    free(t->cell);
    free(t->header);
    memset(t, 0, sizeof *t);
}

/* BUILDDIR/tests/NAME into dir, with "-KERNEL" appended when
 * OPENBLAS_CORETYPE is set: test_kernels.sh runs these tests again under
 * another kernel while `make -j` may still run them under the default,
 * and the two must not write one directory. */
static inline void tsv_out_dir(char *dir, size_t n, const char *name)
{
    const char *b = getenv("SF_BUILDDIR");
    const char *k = getenv("OPENBLAS_CORETYPE");
    snprintf(dir, n, "%s/tests/%s%s%s", b ? b : ".", name, k && k[0] ? "-" : "", k && k[0] ? k : "");
}

/* Run `smoothfold run studies/STUDY.cfg -o DIR -q EXTRA` (DIR emptied
 * first); fails the test on a non-zero exit. */
static inline void tsv_run(const char *study, const char *dir, const char *extra)
{
    const char *b = getenv("SF_BUILDDIR");
    const char *sdir = getenv("SF_SRCDIR");
    if (!b) b = ".";
    if (!sdir) sdir = SF_SRCDIR;
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && '%s/src/smoothfold' run '%s/studies/%s.cfg' -o '%s' -q %s",
             dir, b, sdir, study, dir, extra ? extra : "");
    int rc = system(cmd);
    if (rc != 0) print_error("%s: exit %d\n", cmd, rc);
    assert_int_equal(rc, 0);
}

#endif
