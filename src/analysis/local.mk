# src/analysis/: what is computed from the model: the equilibrium problem,
# the flat start, stability, bifurcation bookkeeping, mobility, reactions,
# dynamics, comparison with reference data.
src_libsmoothfold_a_SOURCES += src/analysis/equilibrium.c src/analysis/equilibrium.h \
	src/analysis/equilibrium_poses.c src/analysis/equilibrium_poses.h \
	src/analysis/poses_rowsel.c src/analysis/poses_rowsel.h \
	src/analysis/flatstart.c src/analysis/flatstart.h src/analysis/flatdescend.c \
	src/analysis/flatcone.c src/analysis/flatcone.h \
	src/analysis/flatcone_rays.c src/analysis/flatcone_impl.h \
	src/analysis/flatstart_sparse.c src/analysis/flatstart_sparse.h \
	src/analysis/flatlimit_sparse.c src/analysis/flatlimit_sparse.h \
	src/analysis/flatrigid.c src/analysis/flatrigid.h \
	src/analysis/start/start.c src/analysis/start/start.h src/analysis/start/start_impl.h \
	src/analysis/start/start_alm.c src/analysis/start/start_kkt.c src/analysis/start/start_cone.c \
	src/analysis/lmi.c src/analysis/lmi.h \
	src/analysis/reactions.c src/analysis/reactions.h \
	src/analysis/mobility.c src/analysis/mobility.h src/analysis/mobility_sparse.c \
	src/analysis/compare.c src/analysis/compare.h src/analysis/compare_impl.h \
	src/analysis/compare_read.c src/analysis/compare_eval.c src/analysis/compare_write.c \
	src/analysis/stability.c src/analysis/stability.h src/analysis/stab_cert.c \
	src/analysis/ldlt.c src/analysis/ldlt.h \
	src/analysis/sstab.c src/analysis/sstab.h \
	src/analysis/sstab_rows.c src/analysis/sstab_rows.h \
	src/analysis/bifurcation.c src/analysis/bifurcation.h \
	src/analysis/dynamics.c src/analysis/dynamics.h src/analysis/dynamics_impl.h \
	src/analysis/dynamics_dae.c \
	src/analysis/boundary.c src/analysis/boundary.h \
	src/analysis/sweep.c src/analysis/sweep_run.c src/analysis/sweep.h \
	src/analysis/multibp.c src/analysis/multibp.h \
	src/analysis/flatswitch.c src/analysis/flatswitch_follow.c src/analysis/flatswitch.h \
	src/analysis/validity.c src/analysis/validity.h src/analysis/tritri.c src/analysis/tritri.h
