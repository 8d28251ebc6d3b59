# src/analysis/sweep/: parameter sweeps: the plan, the runs, resume.
src_libsmoothfold_a_SOURCES += src/analysis/sweep/sweep.c src/analysis/sweep/sweep_run.c src/analysis/sweep/sweep.h
