/* foldread.h - read the crease pattern of a FOLD 1.x file (JSON, with
 * jansson) into an sf_cpattern (cpattern.h).
 *
 * Read: vertices_coords (2-D, or 3-D with z = 0), edges_vertices,
 * edges_assignment (B, M, V, F, U; C and J are refused), edges_foldAngle
 * (degrees, valley positive; null or absent: none), faces_vertices,
 * frame_unit, frame_title, the names smoothfold:vertices_name and
 * smoothfold:edges_name, and file_frames with frame_inherit/frame_parent.
 * The frame read is the first whose frame_classes has "creasePattern"
 * (frame 0 is the top level, file_frames[k] is frame k + 1), or the one
 * asked for.  The pattern is then checked (sf_cp_check).
 *
 * Errors are one line naming the file and the JSON location: line and
 * column for malformed JSON, the field and index otherwise:
 *   p.fold:3:17: malformed JSON: ...
 *   p.fold: edges_vertices[4]: vertex 12 does not exist (vertices_coords has 9)
 */
#ifndef SF_FOLDREAD_H
#define SF_FOLDREAD_H

#include "cpattern.h"

/* frame: -1 for the first crease-pattern frame.  unit: NULL to use the
 * file's frame_unit, else one of m, cm, mm, um, nm, in, pt, unit (= m).
 * *unit_note gets a short description of the unit used (for comments). */
int sf_fold_read(const char *path, int frame, const char *unit,
                 sf_cpattern *cp, char *unit_note, size_t nnote, sf_error *err);

#endif
