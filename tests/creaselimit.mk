# the rigid-origami limit (closed form of the flat-foldable degree-4
# vertex along a Miura actuation path) and symmetric states of symmetric
# sheets (docs/design/crease-limit.md)
check_PROGRAMS += tests/test_creaselimit
TESTS += tests/test_creaselimit
tests_test_creaselimit_SOURCES = tests/test_creaselimit.c
tests_test_creaselimit_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_creaselimit_LDADD = $(SF_TEST_LIBS)
