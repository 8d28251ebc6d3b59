# src/: origami model library and the smoothfold program
noinst_LIBRARIES += src/libsmoothfold.a
src_libsmoothfold_a_SOURCES = src/sf_error.c src/sf_error.h src/pattern.h
bin_PROGRAMS += src/smoothfold
src_smoothfold_SOURCES = src/main.c
src_smoothfold_LDADD = src/libsmoothfold.a continuation/libcont.a $(LDADD_COMMON)
include src/topology.mk
include src/study.mk
