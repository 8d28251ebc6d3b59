# src/analysis/bifurcation/: branch points along a path, branch directions
# at double points, two-parameter continuation of limit and branch points.
src_libsmoothfold_a_SOURCES += src/analysis/bifurcation/bifurcation.c src/analysis/bifurcation/bifurcation.h \
	src/analysis/bifurcation/multibp.c src/analysis/bifurcation/multibp.h \
	src/analysis/bifurcation/boundary.c src/analysis/bifurcation/boundary.h
