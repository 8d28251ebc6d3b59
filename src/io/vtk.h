/* vtk.h - 3-D shapes as VTK XML PolyData (.vtp) and series as ParaView
 * collections (.pvd).  Files are written to a temporary name and renamed
 * when complete.
 *
 * A .vtp holds the rigid faces as polygons (their bodies: crease-pattern
 * faces minus bands and setbacks) and every fold band as a strip of quads,
 * `samples` across the width, straight along the generators.  Cell data:
 *   part        0 = face, 1 = fold band
 *   index       face or fold number, from 1
 *   fold_angle  theta of the fold [rad] (0 on faces)
 *   curvature   kappa at the middle of the quad [1/m] (0 on faces)
 * Point data: displacement [m] from the flat reference sheet.
 */
#ifndef SF_VTK_H
#define SF_VTK_H

#include "kinematics.h"
#include "sf_error.h"

/* Write the configuration q (kinematics evaluated inside) to path, which
 * must end in ".vtp" (SF_EINPUT otherwise, naming the supported ones). */
int sf_vtk_write_shape(const sf_model *m, const double *q, int samples,
                       const char *path, sf_error *err);

/* The same with field data: nfields named numbers (e.g. the parameter p
 * and the row of a shape along a path) in the file's FieldData. */
int sf_vtk_write_shape_fields(const sf_model *m, const double *q, int samples,
                              const char *path, int nfields, const char *const *names,
                              const double *values, sf_error *err);

/* A series of shapes for ParaView: a .pvd naming one .vtp per time. */
typedef struct sf_pvd {
    char path[1024];
    int n, cap;
    double *time;
    char **file;      /* file names relative to the .pvd's directory */
} sf_pvd;

void sf_pvd_init(sf_pvd *p, const char *path);
int sf_pvd_add(sf_pvd *p, double time, const char *file, sf_error *err);
int sf_pvd_write(const sf_pvd *p, sf_error *err);
void sf_pvd_free(sf_pvd *p);

/* Write to path.tmp via the callback, then rename; removes the temporary
 * on failure.  The callback returns 0 on success (SF_EIO with errno set
 * by the failed write: the message gives its strerror).  SIGINT, SIGTERM
 * and SIGHUP are held back while the file is written and renamed, so a
 * killed run leaves complete files or none. */
int sf_write_atomic(const char *path, int (*fill)(void *ctx, void *file),
                    void *ctx, sf_error *err);

#endif
