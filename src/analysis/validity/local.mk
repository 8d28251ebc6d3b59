# src/analysis/validity/: is a computed shape physically possible: fold
# angles, self-intersection.
src_libsmoothfold_a_SOURCES += src/analysis/validity/validity.c src/analysis/validity/validity.h \
	src/analysis/validity/tritri.c src/analysis/validity/tritri.h
