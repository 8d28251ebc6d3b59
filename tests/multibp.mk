# branch switching at multiple branch points (multibp.h): square4-inplane's
# double branch point against the orbit structure of the square's symmetry
check_PROGRAMS += tests/test_multibp
TESTS += tests/test_multibp
tests_test_multibp_SOURCES = tests/test_multibp.c
tests_test_multibp_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_multibp_LDADD = $(SF_TEST_LIBS)
