# energy and equilibrium residual/Jacobian against finite differences and
# closed forms; whole paths against the reference data in ../shared/data
check_PROGRAMS += tests/test_energy tests/test_validation
TESTS += tests/test_energy tests/test_validation
tests_test_energy_SOURCES = tests/test_energy.c
tests_test_energy_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_energy_LDADD = $(SF_TEST_LIBS)
tests_test_validation_SOURCES = tests/test_validation.c
tests_test_validation_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_validation_LDADD = $(SF_TEST_LIBS)
# stability, special points, branch switching and the hard cases
check_PROGRAMS += tests/test_stability
TESTS += tests/test_stability
tests_test_stability_SOURCES = tests/test_stability.c
tests_test_stability_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_stability_LDADD = $(SF_TEST_LIBS)

# the MUMPS wrapper and the sparse stability entry point, against closed forms
check_PROGRAMS += tests/test_sstab
TESTS += tests/test_sstab
tests_test_sstab_SOURCES = tests/test_sstab.c
tests_test_sstab_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_sstab_LDADD = $(SF_TEST_LIBS)

# the cost rules of the bounded effort (docs/design/linear-algebra.md, "Cost"), against closed forms
check_PROGRAMS += tests/test_sstab_cost
TESTS += tests/test_sstab_cost
tests_test_sstab_cost_SOURCES = tests/test_sstab_cost.c
tests_test_sstab_cost_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_sstab_cost_LDADD = $(SF_TEST_LIBS)

# the rank-revealing QR of the constraint rows factorises C^T alone (docs/design/linear-algebra.md, "Cost")
check_PROGRAMS += tests/test_sstab_qr
TESTS += tests/test_sstab_qr
tests_test_sstab_qr_SOURCES = tests/test_sstab_qr.c
tests_test_sstab_qr_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_sstab_qr_LDADD = $(SF_TEST_LIBS)

# stability from the MUMPS inertia against the dense method along paths
TESTS += tests/test_stab_inertia.sh
EXTRA_DIST += tests/test_stab_inertia.sh
