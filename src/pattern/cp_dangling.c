/* cp_dangling.c - folds that end inside a face, left out of the study.
 *
 * A fold whose end is free (no other fold and no outline there) has the
 * same face on both sides.  With rigid faces that face cannot turn about
 * the fold, so its fold angle stays 0 whatever the loads: leaving it out
 * changes no state, energy or stiffness of the rest.  Removing it can
 * free the end of the fold it started from, so the folds are peeled from
 * their free ends inwards (each vertex's count of outline and fold edges;
 * a vertex left with one is a free end), which takes O(V + E).  A fold on
 * a closed path of folds is never free this way; a cluster of folds
 * joined to the rest by nothing stays a hole, which the topology refuses.
 */
#include "cpattern.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int counts(const sf_cpattern *cp, int flat_too, int e)
{
    char a = cp->e[e].assign;
    return a == 'B' || a == 'M' || a == 'V' || a == 'U' || (a == 'F' && flat_too);
}

int sf_cp_drop_dangling(sf_cpattern *cp, int flat_too, char *what, size_t nwhat, sf_error *err)
{
    if (what && nwhat) what[0] = '\0';
    int nv = cp->nv, ne = cp->ne;
    int *deg = calloc((size_t)nv + 1, sizeof *deg), *start = calloc((size_t)nv + 2, sizeof *start);
    int *inc = malloc(sizeof *inc * (size_t)(2 * ne + 1)), *queue = malloc(sizeof *queue * (size_t)(nv + 1));
    char *gone = calloc((size_t)ne + 1, 1);
    if (!deg || !start || !inc || !queue || !gone) {
        free(deg); free(start); free(inc); free(queue); free(gone);
        return -sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int e = 0; e < ne; e++)
        if (counts(cp, flat_too, e)) { start[cp->e[e].a + 1]++; start[cp->e[e].b + 1]++; }
    for (int v = 0; v < nv; v++) start[v + 1] += start[v];
    for (int e = 0; e < ne; e++)
        if (counts(cp, flat_too, e)) {
            inc[start[cp->e[e].a] + deg[cp->e[e].a]++] = e;
            inc[start[cp->e[e].b] + deg[cp->e[e].b]++] = e;
        }
    int nq = 0, head = 0, ndrop = 0;
    for (int v = 0; v < nv; v++)
        if (deg[v] == 1) queue[nq++] = v;
    while (head < nq) {
        int v = queue[head++], e = -1;
        if (deg[v] != 1) continue;
        for (int k = start[v]; k < start[v + 1]; k++)
            if (!gone[inc[k]]) { e = inc[k]; break; }
        if (e < 0 || cp->e[e].assign == 'B') continue;   /* an outline edge never hangs free */
        gone[e] = 1;
        ndrop++;
        deg[v]--;
        int u = cp->e[e].a == v ? cp->e[e].b : cp->e[e].a;
        if (--deg[u] == 1) queue[nq++] = u;
        if (what && ndrop <= 3) {   /* the first few, in millimetres */
            const double *p = cp->v[cp->e[e].a].x, *q = cp->v[cp->e[e].b].x;
            double s = 1e3 * cp->unit;
            size_t l = strlen(what);
            snprintf(what + l, nwhat - l, "%s(%.4g, %.4g)-(%.4g, %.4g) mm", ndrop > 1 ? ", " : "",
                     s * p[0], s * p[1], s * q[0], s * q[1]);
        }
    }
    if (what && ndrop > 3) {
        size_t l = strlen(what);
        snprintf(what + l, nwhat - l, " and %d more", ndrop - 3);
    }
    int k = 0;
    for (int e = 0; e < ne; e++)
        if (!gone[e]) cp->e[k++] = cp->e[e];
    cp->ne = k;
    if (ndrop) cp->nf = 0;   /* faces given in the file no longer match the edges */
    free(deg); free(start); free(inc); free(queue); free(gone);
    return ndrop;
}
