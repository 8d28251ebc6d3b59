# tests/import.mk: crease patterns from the design tools (FOLD and SVG,
# tests/public/), the SVG reader's small languages, and @include confined
# to the study's folder
TESTS += tests/test_import_public.sh tests/test_include.sh tests/test_validity_public.sh
EXTRA_DIST += tests/test_import_public.sh tests/test_include.sh tests/test_validity_public.sh tests/public_check.py \
	tests/public/README.md tests/public/manifest.tsv $(wildcard $(srcdir)/tests/public/*/*) \
	$(wildcard $(srcdir)/tests/bad/svg_*.svg) $(wildcard $(srcdir)/tests/bad/svg_*.expect)
check_PROGRAMS += tests/test_svg
TESTS += tests/test_svg
tests_test_svg_SOURCES = tests/test_svg.c
tests_test_svg_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_svg_LDADD = $(SF_TEST_LIBS)
