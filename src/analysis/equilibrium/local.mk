# src/analysis/equilibrium/: the equilibrium problem in either formulation,
# the pose rows kept, support reactions.
src_libsmoothfold_a_SOURCES += src/analysis/equilibrium/equilibrium.c src/analysis/equilibrium/equilibrium.h \
	src/analysis/equilibrium/equilibrium_poses.c src/analysis/equilibrium/equilibrium_poses.h \
	src/analysis/equilibrium/poses_rowsel.c src/analysis/equilibrium/poses_rowsel.h \
	src/analysis/equilibrium/reactions.c src/analysis/equilibrium/reactions.h
