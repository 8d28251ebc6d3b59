# tests/bending.mk: bending faces (src/pattern/facets.c, docs/guides/bending-faces.md)
check_PROGRAMS += tests/test_facets
TESTS += tests/test_facets
tests_test_facets_SOURCES = tests/test_facets.c
tests_test_facets_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_facets_LDADD = $(SF_TEST_LIBS)
TESTS += tests/test_bending.sh
EXTRA_DIST += tests/test_bending.sh studies/miura-2x2.cfg tests/fold/facet-square.fold \
	studies/twist.cfg studies/hypar-4.cfg studies/miura-2x2-bending.cfg
