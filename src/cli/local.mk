# src/cli/: the smoothfold program: option parsing and one file per command.
src_smoothfold_SOURCES += src/cli/main.c src/cli/commands.c src/cli/commands.h \
	src/cli/run.c src/cli/run_dynamics.c src/cli/run_dynamics.h src/cli/cmp_runs.c src/cli/plot.c \
	src/cli/cmd_pattern.c src/cli/cmd_fold.c \
	src/cli/run_boundary.c src/cli/run_boundary.h
EXTRA_DIST += plots/stability.gp plots/eigenvalues.gp plots/angles.gp plots/trajectory.gp plots/boundary.gp
