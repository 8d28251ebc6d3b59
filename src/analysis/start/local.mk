# src/analysis/start/: leaving the flat state with exact loop closure: the
# limit, sparse and multipliers starts, the tangent cone, branch switching
# at the flat state.
src_libsmoothfold_a_SOURCES += src/analysis/start/flatstart.c src/analysis/start/flatstart.h \
	src/analysis/start/flatdescend.c \
	src/analysis/start/flatcone.c src/analysis/start/flatcone.h \
	src/analysis/start/flatcone_rays.c src/analysis/start/flatcone_impl.h \
	src/analysis/start/flatstart_sparse.c src/analysis/start/flatstart_sparse.h \
	src/analysis/start/flatlimit_sparse.c src/analysis/start/flatlimit_sparse.h \
	src/analysis/start/flatrigid.c src/analysis/start/flatrigid.h \
	src/analysis/start/flatswitch.c src/analysis/start/flatswitch_follow.c src/analysis/start/flatswitch.h \
	src/analysis/start/start.c src/analysis/start/start.h src/analysis/start/start_impl.h \
	src/analysis/start/start_alm.c src/analysis/start/start_kkt.c
