# two-parameter continuation of limit and branch points (boundary.h):
# extended Jacobians against differences; whole boundary runs against
# closed forms
check_PROGRAMS += tests/test_boundary
TESTS += tests/test_boundary tests/test_boundary_runs.sh
EXTRA_DIST += tests/test_boundary_runs.sh
tests_test_boundary_SOURCES = tests/test_boundary.c
tests_test_boundary_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_boundary_LDADD = $(SF_TEST_LIBS)
