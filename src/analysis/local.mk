# src/analysis/: what is computed from the model: the equilibrium problem,
# the flat start, stability, mobility, reactions, dynamics, comparison with
# reference data.
src_libsmoothfold_a_SOURCES += src/analysis/equilibrium.c src/analysis/equilibrium.h \
	src/analysis/flatstart.c src/analysis/flatstart.h \
	src/analysis/reactions.c src/analysis/reactions.h \
	src/analysis/mobility.c src/analysis/mobility.h \
	src/analysis/compare.c src/analysis/compare.h \
	src/analysis/stability.c src/analysis/stability.h \
	src/analysis/dynamics.c src/analysis/dynamics.h \
	src/analysis/sweep.c src/analysis/sweep_run.c src/analysis/sweep.h
