# src/pattern/: the study in memory (pattern.h), its reader (study.c and
# study_*.c, private header study_impl.h) and the crease-pattern topology
# (faces, vertex cycles, face tree); crease patterns as FOLD sees them
# (cpattern.h), the tessellation generators and the FOLD and SVG readers
# (foldread.h; SVG through libxml2, whose flags are added here).
src_libsmoothfold_a_SOURCES += src/pattern/pattern.h \
	src/pattern/study.c src/pattern/study.h src/pattern/study_impl.h \
	src/pattern/study_util.c src/pattern/study_paths.c src/pattern/study_set.c \
	src/pattern/study_check.c src/pattern/study_fill.c src/pattern/study_write.c \
	src/pattern/study_access.c src/pattern/study_include.c \
	src/pattern/topology.c src/pattern/topology.h src/pattern/topology_impl.h \
	src/pattern/topology_geom.c src/pattern/topology_check.c src/pattern/topology_bodies.c \
	src/pattern/topology_grid.c \
	src/pattern/assignment.c src/pattern/facets.c src/pattern/facets.h \
	src/pattern/cpattern.c src/pattern/cpattern.h src/pattern/cp_study.c \
	src/pattern/cp_from_study.c src/pattern/cp_clean.c src/pattern/cp_dangling.c src/pattern/cp_pieces.c \
	src/pattern/foldread.h src/pattern/import.c src/pattern/fold_read.c \
	src/pattern/fold_plane.c src/pattern/fold_plane.h \
	src/pattern/svg_read.c src/pattern/svg_path.c src/pattern/svg_impl.h \
	src/pattern/generators.c src/pattern/generators.h
AM_CFLAGS += $(LIBXML_CFLAGS)
LDADD_COMMON += $(LIBXML_LIBS)
