# tests/cont.mk: unit tests of the continuation engine (continuation/)
check_PROGRAMS += tests/test_cont
TESTS += tests/test_cont
tests_test_cont_SOURCES = tests/test_cont.c
tests_test_cont_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_cont_LDADD = $(SF_TEST_LIBS)
