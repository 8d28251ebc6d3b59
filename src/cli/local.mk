# src/cli/: the smoothfold program: option parsing and one file per command.
src_smoothfold_SOURCES += src/cli/main.c src/cli/commands.c src/cli/commands.h \
	src/cli/run.c src/cli/run_impl.h src/cli/run_equilibrium.c src/cli/run_stability.c \
	src/cli/run_point.c src/cli/run_validity.c src/cli/run_validity.h src/cli/run_output.c src/cli/progress.c src/cli/progress.h \
	src/cli/run_dynamics.c src/cli/run_dynamics.h src/cli/cmp_runs.c src/cli/plot.c \
	src/cli/cmd_pattern.c src/cli/cmd_fold.c src/cli/cmd_keys.c \
	src/cli/run_boundary.c src/cli/run_boundary.h \
	src/cli/sweep.c src/cli/sweep_cli.c src/cli/sweep_cli.h
EXTRA_DIST += plots/sweep.gp src/cli/sweep_mpi.c

# smoothfold-sweep-mpi (sweep_mpi.c): MPI rank 0 hands out the variants of a
# sweep.  Built only with MPI (configure --with-mpi).  It needs the sweep and
# study code and libconfig, nothing numerical: its own link line, with -lmpi
# before $(LIBS) and --as-needed, so that no MPI stub library (MUMPS's
# libmpiseq) that $(LIBS) may hold can stand in for OpenMPI; MPI_CFLAGS come
# first for the same reason (mumps_seq has an mpi.h of its own).
if SF_MPI
bin_PROGRAMS += src/smoothfold-sweep-mpi
src_smoothfold_sweep_mpi_SOURCES = src/cli/sweep_mpi.c src/cli/sweep_cli.c src/cli/sweep_cli.h
src_smoothfold_sweep_mpi_CPPFLAGS = $(MPI_CFLAGS) $(AM_CPPFLAGS)
src_smoothfold_sweep_mpi_LDFLAGS = -Wl,--as-needed
src_smoothfold_sweep_mpi_LDADD = $(MPI_LIBS) src/libsmoothfold.a $(LIBCONFIG_LIBS) -lm
endif
EXTRA_DIST += plots/stability.gp plots/eigenvalues.gp plots/angles.gp plots/trajectory.gp plots/boundary.gp

# The man page, made by help2man from the program's own --help and each
# command's --help, so that it says what the program says.  The per-command
# texts go into the COMMANDS section through help2man's include file.
man1_MANS = src/smoothfold.1
EXTRA_DIST += src/cli/man.h2m
CLEANFILES += src/smoothfold.1 src/smoothfold.h2m
src/smoothfold.1: src/smoothfold$(EXEEXT) $(srcdir)/src/cli/man.h2m
	$(AM_V_GEN){ cat $(srcdir)/src/cli/man.h2m; printf '\n[COMMANDS]\n'; \
	  for c in $$(./src/smoothfold$(EXEEXT) --help | $(AWK) '/^Commands/ {on = 1; next} /^Options:/ {on = 0} on && /^  [a-z]/ {print $$1}'); do \
	    case $$c in import|export) continue;; esac; \
	    printf '.SS %s\n.nf\n' "$$c"; \
	    ./src/smoothfold$(EXEEXT) $$c --help | sed -e 's/\\/\\e/g' -e "s/^\([.']\)/\\\\\&\1/"; \
	    printf '.fi\n'; \
	  done; } > src/smoothfold.h2m && \
	$(HELP2MAN) --no-info --no-discard-stderr --section=1 \
	  --name='structural analysis of origami sheets with smooth folds' \
	  --include=src/smoothfold.h2m --output=$@ ./src/smoothfold$(EXEEXT)

# Bash completion (commands, options, study keys, all asked of the binary).
dist_bashcompletion_DATA = src/cli/completion/smoothfold
