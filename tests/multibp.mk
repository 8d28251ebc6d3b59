# branch switching at multiple branch points (multibp.h): square4-inplane's
# double branch point against the orbit structure of the square's symmetry
check_PROGRAMS += tests/test_multibp
TESTS += tests/test_multibp
tests_test_multibp_SOURCES = tests/test_multibp.c
tests_test_multibp_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_multibp_LDADD = $(SF_TEST_LIBS)
# the step bound near predicted eigenvalue crossings (analysis.step_bound)
TESTS += tests/test_step_bound.sh
EXTRA_DIST += tests/test_step_bound.sh
