# tests/cont.mk: unit tests of the continuation engine (continuation/)
check_PROGRAMS += tests/test_cont tests/test_cont_det
TESTS += tests/test_cont tests/test_cont_det
tests_test_cont_SOURCES = tests/test_cont.c tests/cont_test.h
tests_test_cont_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_cont_LDADD = $(SF_TEST_LIBS)
tests_test_cont_det_SOURCES = tests/test_cont_det.c tests/cont_test.h
tests_test_cont_det_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_cont_det_LDADD = $(SF_TEST_LIBS)
# the reusing corrector: the same paths as KINSOL's with fewer factorisations
check_PROGRAMS += tests/test_cont_reuse
TESTS += tests/test_cont_reuse
tests_test_cont_reuse_SOURCES = tests/test_cont_reuse.c tests/cont_test.h
tests_test_cont_reuse_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_cont_reuse_LDADD = $(SF_TEST_LIBS)
# block elimination on the LDL^T of a symmetric Jy against the bordered LU
check_PROGRAMS += tests/test_cont_block
TESTS += tests/test_cont_block
tests_test_cont_block_SOURCES = tests/test_cont_block.c tests/cont_test.h
tests_test_cont_block_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_cont_block_LDADD = $(SF_TEST_LIBS)
# the corrector's MUMPS solves (dmumps_c wrapped by the linker)
check_PROGRAMS += tests/test_cont_solves
TESTS += tests/test_cont_solves
tests_test_cont_solves_SOURCES = tests/test_cont_solves.c tests/cont_test.h
tests_test_cont_solves_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_cont_solves_LDFLAGS = -Wl,--wrap=dmumps_c
tests_test_cont_solves_LDADD = $(SF_TEST_LIBS)
# Newton at fixed p in cont_start: the LDL^T of a symmetric Jy, the line
# search as fallback (dmumps_c wrapped by the linker)
check_PROGRAMS += tests/test_cont_start
TESTS += tests/test_cont_start
tests_test_cont_start_SOURCES = tests/test_cont_start.c tests/cont_test.h
tests_test_cont_start_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_cont_start_LDFLAGS = -Wl,--wrap=dmumps_c
tests_test_cont_start_LDADD = $(SF_TEST_LIBS)
# options for long steps: the second-order predictor, the scaled arclength
check_PROGRAMS += tests/test_cont_bigstep
TESTS += tests/test_cont_bigstep
tests_test_cont_bigstep_SOURCES = tests/test_cont_bigstep.c tests/cont_test.h
tests_test_cont_bigstep_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_cont_bigstep_LDADD = $(SF_TEST_LIBS)
