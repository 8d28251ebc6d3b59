# tests/paths.mk: exact paths off the flat state, mobility, reactions
check_PROGRAMS += tests/test_paths
TESTS += tests/test_paths tests/test_reactions.sh tests/test_run_exact.sh
tests_test_paths_SOURCES = tests/test_paths.c
tests_test_paths_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_paths_LDADD = $(SF_TEST_LIBS)
EXTRA_DIST += tests/test_reactions.sh tests/test_run_exact.sh tests/studies/deg4.cfg tests/studies/lever.cfg \
	tests/studies/tip.cfg
# exact closure from the flat state: the tangent cone (docs/flatstart.md)
TESTS += tests/test_flatstart.sh
EXTRA_DIST += tests/test_flatstart.sh
# the sparse start at the flat state for face poses (docs/flatstart.md)
TESTS += tests/test_flatstart_sparse.sh
EXTRA_DIST += tests/test_flatstart_sparse.sh
