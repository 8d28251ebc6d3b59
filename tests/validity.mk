# tests/validity.mk: the physical-validity checks (src/analysis/validity/validity.h)
check_PROGRAMS += tests/test_validity
TESTS += tests/test_validity
tests_test_validity_SOURCES = tests/test_validity.c
tests_test_validity_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_validity_LDADD = $(SF_TEST_LIBS)
# the warning column of trajectories and stability boundaries
TESTS += tests/test_validity_runs.sh
EXTRA_DIST += tests/test_validity_runs.sh
