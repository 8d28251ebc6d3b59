# src/: the origami library (libsmoothfold.a, one folder per stage of the
# data flow, see src/README.md) and the smoothfold program (src/cli/).
noinst_LIBRARIES += src/libsmoothfold.a
src_libsmoothfold_a_SOURCES = src/sf_error.c src/sf_error.h
bin_PROGRAMS += src/smoothfold
src_smoothfold_SOURCES =
src_smoothfold_LDADD = src/libsmoothfold.a continuation/libcont.a $(LDADD_COMMON)
include src/pattern/local.mk
include src/model/local.mk
include src/analysis/local.mk
include src/io/local.mk
include src/cli/local.mk
