# tests/topology.mk: fragment owned by one module
check_PROGRAMS += tests/test_topology
TESTS += tests/test_topology
tests_test_topology_SOURCES = tests/test_topology.c
tests_test_topology_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_topology_LDADD = $(SF_TEST_LIBS)
EXTRA_DIST += $(wildcard $(srcdir)/tests/bad/topo_*.cfg) $(wildcard $(srcdir)/tests/bad/topo_*.expect)
