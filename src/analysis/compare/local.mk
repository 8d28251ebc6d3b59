# src/analysis/compare/: a computed path against reference data.
src_libsmoothfold_a_SOURCES += src/analysis/compare/compare.c src/analysis/compare/compare.h \
	src/analysis/compare/compare_impl.h \
	src/analysis/compare/compare_read.c src/analysis/compare/compare_eval.c src/analysis/compare/compare_write.c
