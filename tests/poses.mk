# the face-pose formulation: derivatives against finite differences, the
# same equilibria as the fold formulation, linear growth of the nonzeros
check_PROGRAMS += tests/test_poses
TESTS += tests/test_poses
tests_test_poses_SOURCES = tests/test_poses.c
tests_test_poses_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_poses_LDADD = $(SF_TEST_LIBS)
EXTRA_DIST += tests/studies/miura2.cfg tests/studies/miura4.cfg bench/miura-study.sh
TESTS += tests/test_poses_run.sh
EXTRA_DIST += tests/test_poses_run.sh
# the redundant fold rows of the pose formulation removed (poses_rowsel.c)
check_PROGRAMS += tests/test_rowsel
TESTS += tests/test_rowsel
tests_test_rowsel_SOURCES = tests/test_rowsel.c
tests_test_rowsel_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_rowsel_LDADD = $(SF_TEST_LIBS)
# stability where the loop rows are redundant and lose rank: the
# self-stress certificate (stab_cert.c) against the energy on closed states
check_PROGRAMS += tests/test_stab_cert
TESTS += tests/test_stab_cert
tests_test_stab_cert_SOURCES = tests/test_stab_cert.c
tests_test_stab_cert_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_stab_cert_LDADD = $(SF_TEST_LIBS)
EXTRA_DIST += tests/studies/waterbomb-2x2-all.cfg
# the wrench of a fold on its faces (sf_peq_fold_wrench) against statics
check_PROGRAMS += tests/test_fold_wrench
TESTS += tests/test_fold_wrench
tests_test_fold_wrench_SOURCES = tests/test_fold_wrench.c
tests_test_fold_wrench_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_fold_wrench_LDADD = $(SF_TEST_LIBS)
# analysis.step_norm = "rms": as many points on a large sheet as on a small one
TESTS += tests/test_step_norm.sh
EXTRA_DIST += tests/test_step_norm.sh
# the "auto" defaults of solver.formulation, analysis.flat_start and
# analysis.step_norm: by size, the small-sheet choices unchanged
TESTS += tests/test_auto_keys.sh
EXTRA_DIST += tests/test_auto_keys.sh
