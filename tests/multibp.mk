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
# switching at the flat state with exact closure (flatswitch.h): square4-inplane
# exact, cone solutions against D4, branches, the penalty limit
check_PROGRAMS += tests/test_flatswitch
TESTS += tests/test_flatswitch
tests_test_flatswitch_SOURCES = tests/test_flatswitch.c
tests_test_flatswitch_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_flatswitch_LDADD = $(SF_TEST_LIBS)
TESTS += tests/test_flatswitch_cli.sh
EXTRA_DIST += tests/test_flatswitch_cli.sh
