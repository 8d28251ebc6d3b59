# src/: origami model library and the smoothfold program
noinst_LIBRARIES += src/libsmoothfold.a
src_libsmoothfold_a_SOURCES = src/sf_error.c src/sf_error.h src/pattern.h
bin_PROGRAMS += src/smoothfold
src_smoothfold_SOURCES = src/main.c
src_smoothfold_LDADD = src/libsmoothfold.a continuation/libcont.a $(LDADD_COMMON)
include src/topology.mk
include src/study.mk
src_libsmoothfold_a_SOURCES += src/shape.c src/shape.h src/kinematics.c src/kinematics.h src/topology.h
src_libsmoothfold_a_SOURCES += src/vtk.c src/vtk.h src/scene.c src/scene.h
src_smoothfold_SOURCES += src/commands.c src/commands.h
src_libsmoothfold_a_SOURCES += src/energy.c src/energy.h
src_libsmoothfold_a_SOURCES += src/equilibrium.c src/equilibrium.h
src_libsmoothfold_a_SOURCES += src/flatstart.c src/flatstart.h
src_libsmoothfold_a_SOURCES += src/reactions.c src/reactions.h
src_libsmoothfold_a_SOURCES += src/mobility.c src/mobility.h
src_libsmoothfold_a_SOURCES += src/compare.c src/compare.h
src_smoothfold_SOURCES += src/run.c
EXTRA_DIST += plots/stability.gp plots/eigenvalues.gp plots/angles.gp
src_libsmoothfold_a_SOURCES += src/stability.c src/stability.h
src_libsmoothfold_a_SOURCES += src/dynamics.c src/dynamics.h
src_smoothfold_SOURCES += src/run_dynamics.c src/run_dynamics.h
EXTRA_DIST += plots/trajectory.gp
src_libsmoothfold_a_SOURCES += src/outbuf.c src/outbuf.h
