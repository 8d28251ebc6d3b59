/* cp_pieces.c - a file that draws several sheets (Origami Simulator's
 * sheets of examples, Rabbit Ear's two-bird-cp.fold): its boundary edges
 * form several loops.  A loop inside no other is a sheet; a loop inside a
 * sheet is a hole in it.  Sheets are numbered by area, largest first (ties
 * by their lowest vertex index), and --piece=N keeps sheet N with the lines
 * inside it.  A smoothfold sheet has one outline, so a hole is refused.
 */
#include "cpattern.h"
#include "topology.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct loop {
    int start, n;      /* into the walk order */
    double area;       /* absolute */
    int minv;          /* lowest vertex index, for ties */
    int parent;        /* the smallest loop around it, -1: none */
} loop;

static const double *P(const sf_cpattern *cp, int v) { return cp->v[v].x; }

/* Is p inside loop L (or on it)?  xy: the walked vertices' coordinates */
static int inside(double (*xy)[2], const loop *L, const double *p)
{
    sf_polygon poly = {L->n, xy + L->start};
    return sf_polygon_contains(&poly, p, 0.0);
}

static const loop *g_loops;   /* qsort has no context in C99: set while sorting */

static int cmp_piece(const void *x, const void *y)
{
    const loop *a = &g_loops[*(const int *)x], *b = &g_loops[*(const int *)y];
    if (a->area != b->area) return a->area > b->area ? -1 : 1;
    return a->minv - b->minv;
}

int sf_cp_pick_piece(sf_cpattern *cp, int piece, const char *where, char *note, size_t nnote, sf_error *err)
{
    if (note && nnote) note[0] = '\0';
    int nv = cp->nv, ne = cp->ne, rc = SF_OK;
    int *deg = calloc((size_t)nv + 1, sizeof *deg), *adj = malloc(sizeof *adj * (size_t)(2 * nv + 2));
    int *walk = malloc(sizeof *walk * (size_t)(ne + 1)), *vloop = malloc(sizeof *vloop * (size_t)(nv + 1));
    loop *L = malloc(sizeof *L * (size_t)(ne + 1));
    int *order = malloc(sizeof *order * (size_t)(ne + 1));
    double (*xy)[2] = malloc(sizeof *xy * (size_t)(ne + 1));
    if (!deg || !adj || !walk || !vloop || !L || !order || !xy) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); goto done; }
    /* the boundary graph; anything but 2 edges at each of its vertices is
     * left to sf_cp_check's messages */
    for (int e = 0; e < ne; e++) {
        if (cp->e[e].assign != 'B') continue;
        int ends[2] = {cp->e[e].a, cp->e[e].b};
        for (int k = 0; k < 2; k++) {
            int v = ends[k];
            if (deg[v] >= 2) goto done;
            adj[2 * v + deg[v]++] = ends[1 - k];
        }
    }
    for (int v = 0; v < nv; v++) {
        if (deg[v] == 1) goto done;
        vloop[v] = -1;
    }
    int nl = 0, nw = 0;
    for (int v0 = 0; v0 < nv; v0++) {
        if (deg[v0] != 2 || vloop[v0] >= 0) continue;
        loop *l = &L[nl];
        l->start = nw;
        l->minv = v0;
        l->parent = -1;
        int prev = -1, v = v0;
        do {
            vloop[v] = nl;
            xy[nw][0] = P(cp, v)[0];
            xy[nw][1] = P(cp, v)[1];
            walk[nw++] = v;
            int next = adj[2 * v] != prev ? adj[2 * v] : adj[2 * v + 1];
            prev = v;
            v = next;
        } while (v != v0 && vloop[v] < 0);
        l->n = nw - l->start;
        double a = 0;
        for (int i = 0; i < l->n; i++) {
            const double *p = P(cp, walk[l->start + i]), *q = P(cp, walk[l->start + (i + 1) % l->n]);
            a += p[0] * q[1] - q[0] * p[1];
        }
        l->area = 0.5 * fabs(a);
        nl++;
    }
    if (nl <= 1) {
        if (piece > 1) rc = sf_fail(err, SF_EINPUT, "%s: --piece=%d: the file draws one sheet", where, piece);
        goto done;
    }
    /* nesting: the smallest loop that holds a vertex of this one */
    for (int i = 0; i < nl; i++)
        for (int j = 0; j < nl; j++)
            if (j != i && L[j].area > L[i].area && inside(xy, &L[j], P(cp, walk[L[i].start])) &&
                (L[i].parent < 0 || L[j].area < L[L[i].parent].area))
                L[i].parent = j;
    int np = 0, nholes = 0;
    for (int i = 0; i < nl; i++) {
        if (L[i].parent < 0) order[np++] = i;
        else nholes++;
    }
    g_loops = L;
    qsort(order, (size_t)np, sizeof *order, cmp_piece);
    if (piece <= 0) {
        if (np == 1) {
            int h = 0;
            while (L[h].parent < 0) h++;
            const double *x = P(cp, walk[L[h].start]);
            rc = sf_fail(err, SF_EINPUT, "%s: the sheet has %d hole%s (a boundary loop inside its outline%s, "
                         "through (%g, %g)): a smoothfold sheet has one outline and no holes", where, nholes,
                         nholes > 1 ? "s" : "", nholes > 1 ? "; the first" : "", x[0], x[1]);
        }
        else {
            char holes[40] = "";
            if (nholes) snprintf(holes, sizeof holes, " (and %d hole%s)", nholes, nholes > 1 ? "s" : "");
            rc = sf_fail(err, SF_EINPUT, "%s: the file draws %d separate sheets%s: --piece=N imports sheet N alone "
                         "(1 the largest, %d the smallest)", where, np, holes, np);
        }
        goto done;
    }
    if (piece > np) {
        rc = sf_fail(err, SF_EINPUT, "%s: --piece=%d: the file draws %d sheets", where, piece, np);
        goto done;
    }
    int keep = order[piece - 1];
    for (int i = 0; i < nl; i++)
        if (L[i].parent == keep) {
            rc = sf_fail(err, SF_EINPUT, "%s: --piece=%d: that sheet has a hole (a boundary loop inside it, "
                         "through (%g, %g)): a smoothfold sheet has one outline and no holes", where, piece,
                         P(cp, walk[L[i].start])[0], P(cp, walk[L[i].start])[1]);
            goto done;
        }
    /* keep the sheet's outline and the lines inside it */
    int k = 0;
    for (int e = 0; e < ne; e++) {
        const sf_cp_edge *E = &cp->e[e];
        int in;
        if (E->assign == 'B') in = vloop[E->a] == keep;
        else {
            double m[2] = {0.5 * (P(cp, E->a)[0] + P(cp, E->b)[0]), 0.5 * (P(cp, E->a)[1] + P(cp, E->b)[1])};
            in = inside(xy, &L[keep], m);
        }
        if (in) cp->e[k++] = *E;
    }
    int kept = k;
    cp->ne = kept;
    /* vertices of the kept edges only, in their old order */
    int *map = deg;   /* reused: old index -> new, -1 for dropped */
    for (int v = 0; v < nv; v++) map[v] = -1;
    for (int e = 0; e < kept; e++) map[cp->e[e].a] = map[cp->e[e].b] = 0;
    int n2 = 0;
    for (int v = 0; v < nv; v++)
        if (map[v] == 0) { cp->v[n2] = cp->v[v]; map[v] = n2++; }
    cp->nv = n2;
    for (int e = 0; e < kept; e++) { cp->e[e].a = map[cp->e[e].a]; cp->e[e].b = map[cp->e[e].b]; }
    if (cp->nf) {
        free(cp->face_start); free(cp->face_verts);
        cp->face_start = cp->face_verts = NULL;
        cp->nf = 0;
    }
    if (note)
        snprintf(note, nnote, "--piece=%d: sheet %d of the %d the file draws (numbered by area, largest first), "
                 "%d edges; the others left out", piece, piece, np, kept);
done:
    free(deg); free(adj); free(walk); free(vloop); free(L); free(order); free(xy);
    return rc;
}
