# src/analysis/stability/: eigenvalues and inertia of the constrained
# Hessian (dense and sparse), the self-stress certificate, mobility.
src_libsmoothfold_a_SOURCES += src/analysis/stability/stability.c src/analysis/stability/stability.h \
	src/analysis/stability/stab_cert.c \
	src/analysis/stability/sstab.c src/analysis/stability/sstab.h \
	src/analysis/stability/sstab_rows.c src/analysis/stability/sstab_rows.h \
	src/analysis/stability/mobility.c src/analysis/stability/mobility.h src/analysis/stability/mobility_sparse.c src/analysis/stability/mobility_sos.c
