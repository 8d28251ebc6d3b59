# tests/: unit, regression and hard-case tests (cmocka, TAP output)
SF_TEST_LIBS = src/libsmoothfold.a continuation/libcont.a $(CMOCKA_LIBS) $(LDADD_COMMON)
SF_TEST_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
include tests/cont.mk
include tests/topology.mk
include tests/study.mk

check_PROGRAMS += tests/test_shape
TESTS += tests/test_shape
tests_test_shape_SOURCES = tests/test_shape.c
tests_test_shape_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_shape_LDADD = $(SF_TEST_LIBS)

check_PROGRAMS += tests/test_kinematics
TESTS += tests/test_kinematics
tests_test_kinematics_SOURCES = tests/test_kinematics.c
tests_test_kinematics_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_kinematics_LDADD = $(SF_TEST_LIBS)

# a non-finite number is an error where a row is added, never a 0 in a file
check_PROGRAMS += tests/test_finite
TESTS += tests/test_finite
tests_test_finite_SOURCES = tests/test_finite.c
tests_test_finite_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_finite_LDADD = $(SF_TEST_LIBS)

# broken studies and their messages, through the program
TESTS += tests/test_bad_input.sh
EXTRA_DIST += tests/test_bad_input.sh
TESTS += tests/test_vtk.sh
EXTRA_DIST += tests/test_vtk.sh
include tests/equilibrium.mk
include tests/poses.mk
EXTRA_DIST += tests/sf_test.h tests/check_test.h tests/tap.sh
include tests/dynamics.mk
include tests/paths.mk
include tests/accuracy.mk
include tests/cli.mk
include tests/bifurcation.mk
include tests/pattern.mk
include tests/bending.mk
include tests/boundary.mk
include tests/multibp.mk
include tests/creaselimit.mk
include tests/validity.mk
include tests/docs.mk
# sweeps, serially and under mpirun (src/analysis/sweep/sweep.h, docs/guides/sweeps.md)
check_PROGRAMS += tests/test_sweep_plan
TESTS += tests/test_sweep_plan tests/test_sweep.sh
tests_test_sweep_plan_SOURCES = tests/test_sweep_plan.c
tests_test_sweep_plan_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_sweep_plan_LDADD = $(SF_TEST_LIBS)
EXTRA_DIST += tests/test_sweep.sh
include tests/import.mk
