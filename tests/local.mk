# tests/: unit, regression and hard-case tests (cmocka, TAP output)
SF_TEST_LIBS = src/libsmoothfold.a continuation/libcont.a $(CMOCKA_LIBS) $(LDADD_COMMON)
SF_TEST_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
include tests/cont.mk
include tests/topology.mk
include tests/study.mk
