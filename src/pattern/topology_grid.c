/* topology_grid.c - the pairs of nearby items that the checks of
 * topology_check.c test, without a loop over all pairs: the items' boxes
 * in a uniform grid of about one cell per item over their extent, so that
 * on a crease pattern of short folds the checks grow linearly with the
 * folds (a loop over all pairs took 1.7 s of `smoothfold check` on the
 * 31 x 31 Miura sheet, 7440 folds). */
#include "topology_impl.h"

#include <math.h>
#include <stdlib.h>

static int is_empty(const tp_box *b) { return !(b->lo[0] <= b->hi[0] && b->lo[1] <= b->hi[1]); }

void tp_box_empty(tp_box *b)
{
    b->lo[0] = b->lo[1] = INFINITY;
    b->hi[0] = b->hi[1] = -INFINITY;
}

void tp_box_add(tp_box *b, const double p[2])
{
    for (int k = 0; k < 2; k++) {
        if (p[k] < b->lo[k]) b->lo[k] = p[k];
        if (p[k] > b->hi[k]) b->hi[k] = p[k];
    }
}

typedef struct grid {
    double lo[2], w[2];   /* origin and cell size per axis (0: one cell) */
    int n[2];
} grid;

static int cell_of(const grid *g, int k, double x)
{
    if (!(g->w[k] > 0.0)) return 0;
    double c = floor((x - g->lo[k]) / g->w[k]);
    if (!(c >= 0.0)) return 0;               /* also for a NaN */
    if (c >= g->n[k] - 1) return g->n[k] - 1;
    return (int)c;
}

/* Cell range of [lo - grow, hi + grow] on both axes. */
static void cell_range(const grid *g, const tp_box *b, double grow, int c0[2], int c1[2])
{
    for (int k = 0; k < 2; k++) {
        c0[k] = cell_of(g, k, b->lo[k] - grow);
        c1[k] = cell_of(g, k, b->hi[k] + grow);
    }
}

int tp_box_pairs(int na, const tp_box *A, int nb, const tp_box *Bx, double tol,
                 void (*visit)(void *ctx, int a, int b), void *ctx)
{
    int self = Bx == NULL;
    const tp_box *S = self ? A : Bx;
    int ns = self ? na : nb;
    if (na <= 0 || ns <= 0) return 0;
    grid g;
    tp_box ext;
    tp_box_empty(&ext);
    for (int a = 0; a < na; a++)
        if (!is_empty(&A[a])) {
            tp_box_add(&ext, A[a].lo);
            tp_box_add(&ext, A[a].hi);
        }
    for (int b = 0; b < ns; b++)
        if (!is_empty(&S[b])) {
            tp_box_add(&ext, S[b].lo);
            tp_box_add(&ext, S[b].hi);
        }
    if (is_empty(&ext)) return 0;
    /* about one cell per item: square cells of side sqrt(area / items),
     * at most 2 (na + ns) + 1 cells along an axis */
    double W = ext.hi[0] - ext.lo[0], H = ext.hi[1] - ext.lo[1];
    double items = (double)na + ns, side = W > 0 && H > 0 ? sqrt(W * H / items) : fmax(W, H) / items;
    for (int k = 0; k < 2; k++) {
        double len = k ? H : W;
        g.lo[k] = ext.lo[k];
        g.n[k] = side > 0 && len > 0 ? (int)fmin(ceil(len / side), 2.0 * items + 1.0) : 1;
        if (g.n[k] < 1) g.n[k] = 1;
        g.w[k] = len > 0 ? len / g.n[k] : 0.0;
    }
    size_t ncell = (size_t)g.n[0] * g.n[1];
    /* the items of S in every cell their box grown by tol touches (CSR) */
    size_t *first = calloc(ncell + 1, sizeof *first);
    int *stamp = malloc(sizeof(int) * (size_t)ns);
    int rc = -1, *items_of = NULL;
    if (!first || !stamp) goto done;
    for (int pass = 0; pass < 2; pass++) {
        for (int b = 0; b < ns; b++) {
            if (is_empty(&S[b])) continue;
            int c0[2], c1[2];
            cell_range(&g, &S[b], tol, c0, c1);
            for (int y = c0[1]; y <= c1[1]; y++)
                for (int x = c0[0]; x <= c1[0]; x++) {
                    size_t c = (size_t)y * g.n[0] + x;
                    if (pass == 0) first[c + 1]++;
                    else items_of[first[c]++] = b;
                }
        }
        if (pass == 0) {
            for (size_t c = 0; c < ncell; c++) first[c + 1] += first[c];
            items_of = malloc(sizeof(int) * (first[ncell] + 1));
            if (!items_of) goto done;
        } else {
            /* first[c] now points past cell c: shift back */
            for (size_t c = ncell; c > 0; c--) first[c] = first[c - 1];
            first[0] = 0;
        }
    }
    for (int b = 0; b < ns; b++) stamp[b] = -1;
    for (int a = 0; a < na; a++) {
        if (is_empty(&A[a])) continue;
        int c0[2], c1[2];
        cell_range(&g, &A[a], 0.0, c0, c1);
        for (int y = c0[1]; y <= c1[1]; y++)
            for (int x = c0[0]; x <= c1[0]; x++) {
                size_t c = (size_t)y * g.n[0] + x;
                for (size_t e = first[c]; e < first[c + 1]; e++) {
                    int b = items_of[e];
                    if ((self && b >= a) || stamp[b] == a) continue;
                    stamp[b] = a;
                    if (A[a].lo[0] <= S[b].hi[0] + tol && S[b].lo[0] <= A[a].hi[0] + tol &&
                        A[a].lo[1] <= S[b].hi[1] + tol && S[b].lo[1] <= A[a].hi[1] + tol)
                        visit(ctx, a, b);
                }
            }
    }
    rc = 0;
done:
    free(first);
    free(stamp);
    free(items_of);
    return rc;
}
