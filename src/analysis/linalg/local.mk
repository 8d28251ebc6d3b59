# src/analysis/linalg/: MUMPS LDL^T with inertia, DSDP's eigenvalue LMI.
src_libsmoothfold_a_SOURCES += src/analysis/linalg/ldlt.c src/analysis/linalg/ldlt.h \
	src/analysis/linalg/lmi.c src/analysis/linalg/lmi.h
