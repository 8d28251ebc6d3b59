# tests/topology.mk: fragment owned by one module
check_PROGRAMS += tests/test_topology tests/test_topology_errors
TESTS += tests/test_topology tests/test_topology_errors
tests_test_topology_SOURCES = tests/test_topology.c tests/topo_pat.c tests/topo_pat.h
tests_test_topology_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_topology_LDADD = $(SF_TEST_LIBS)
tests_test_topology_errors_SOURCES = tests/test_topology_errors.c tests/topo_pat.c tests/topo_pat.h
tests_test_topology_errors_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_topology_errors_LDADD = $(SF_TEST_LIBS)
EXTRA_DIST += $(wildcard $(srcdir)/tests/bad/topo_*.cfg) $(wildcard $(srcdir)/tests/bad/topo_*.expect)
# the nearby pairs the topology checks test, against all pairs
check_PROGRAMS += tests/test_check_pairs
TESTS += tests/test_check_pairs
tests_test_check_pairs_SOURCES = tests/test_check_pairs.c
tests_test_check_pairs_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_check_pairs_LDADD = $(SF_TEST_LIBS)
