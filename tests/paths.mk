# tests/paths.mk: exact paths off the flat state, mobility, reactions
check_PROGRAMS += tests/test_paths
TESTS += tests/test_paths tests/test_reactions.sh tests/test_run_exact.sh
tests_test_paths_SOURCES = tests/test_paths.c
tests_test_paths_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_paths_LDADD = $(SF_TEST_LIBS)
EXTRA_DIST += tests/test_reactions.sh tests/test_run_exact.sh tests/studies/deg4.cfg tests/studies/deg3.cfg tests/studies/lever.cfg \
	tests/studies/tip.cfg
# exact closure from the flat state: the tangent cone (docs/flatstart.md)
TESTS += tests/test_flatstart.sh
EXTRA_DIST += tests/test_flatstart.sh
# the start by the method of multipliers (docs/design/start.md)
TESTS += tests/test_start.sh
EXTRA_DIST += tests/test_start.sh
# the sparse start at the flat state for face poses (docs/flatstart.md)
TESTS += tests/test_flatstart_sparse.sh tests/test_loadpath.sh
EXTRA_DIST += tests/test_flatstart_sparse.sh tests/test_loadpath.sh
# the cost of the sparse start's limit problem (docs/flatstart.md)
TESTS += tests/test_flatstart_cost.sh
EXTRA_DIST += tests/test_flatstart_cost.sh

# the local loop rows of a vertex and the sparse first-order mobility
check_PROGRAMS += tests/test_mobility_sparse
TESTS += tests/test_mobility_sparse
tests_test_mobility_sparse_SOURCES = tests/test_mobility_sparse.c
tests_test_mobility_sparse_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_mobility_sparse_LDADD = $(SF_TEST_LIBS)

# the work of check's mobility analysis grows linearly with the folds
check_PROGRAMS += tests/test_check_cost
TESTS += tests/test_check_cost
tests_test_check_cost_SOURCES = tests/test_check_cost.c
tests_test_check_cost_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_check_cost_LDADD = $(SF_TEST_LIBS)
# results independent of the BLAS kernel (OPENBLAS_CORETYPE)
TESTS += tests/test_kernels.sh
EXTRA_DIST += tests/test_kernels.sh
