# src/analysis/dynamics/: folding trajectories in time (IDA).
src_libsmoothfold_a_SOURCES += src/analysis/dynamics/dynamics.c src/analysis/dynamics/dynamics.h \
	src/analysis/dynamics/dynamics_impl.h src/analysis/dynamics/dynamics_dae.c
