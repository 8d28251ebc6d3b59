# tests/pattern.mk: crease patterns, generators and FOLD files
check_PROGRAMS += tests/test_pattern
TESTS += tests/test_pattern
tests_test_pattern_SOURCES = tests/test_pattern.c
tests_test_pattern_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_pattern_LDADD = $(SF_TEST_LIBS)
TESTS += tests/test_pattern_cli.sh
EXTRA_DIST += tests/test_pattern_cli.sh
EXTRA_DIST += $(wildcard $(srcdir)/tests/bad/study_assignment_*.cfg) \
	$(wildcard $(srcdir)/tests/bad/study_assignment_*.expect)
check_PROGRAMS += tests/test_fold
TESTS += tests/test_fold
tests_test_fold_SOURCES = tests/test_fold.c
tests_test_fold_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_fold_LDADD = $(SF_TEST_LIBS)
TESTS += tests/test_fold_cli.sh
EXTRA_DIST += tests/test_fold_cli.sh tests/fold/README.md $(wildcard $(srcdir)/tests/fold/*.fold) \
	$(wildcard $(srcdir)/tests/bad/fold_*.fold) $(wildcard $(srcdir)/tests/bad/fold_*.expect)
TESTS += tests/test_fold_npm.sh
EXTRA_DIST += tests/test_fold_npm.sh tests/fold_check.js
EXTRA_DIST += plots/shape.gp plots/vtp2gp.awk plots/pattern-pictures.sh
