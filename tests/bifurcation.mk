# the bifurcation bookkeeping (src/analysis/bifurcation/bifurcation.h) on its own:
# crossings located against closed forms and bisection, branch switching
check_PROGRAMS += tests/test_bifurcation
TESTS += tests/test_bifurcation
tests_test_bifurcation_SOURCES = tests/test_bifurcation.c
tests_test_bifurcation_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_bifurcation_LDADD = $(SF_TEST_LIBS)
# helpers shared by test_bifurcation, test_stability and test_multibp, and
# the tests' reader of the TSV files `smoothfold run` writes
EXTRA_DIST += tests/stab_test.h tests/tsv_test.h tests/d4_test.h
# the empty morse field of an index the inertia cannot decide (Miura 4x4 load)
TESTS += tests/test_morse_unknown.sh
EXTRA_DIST += tests/test_morse_unknown.sh
