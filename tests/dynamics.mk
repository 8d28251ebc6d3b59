# tests/dynamics.mk: folding trajectories (src/analysis/dynamics/dynamics.c) and the dynamics
# run command
check_PROGRAMS += tests/test_dynamics
TESTS += tests/test_dynamics
tests_test_dynamics_SOURCES = tests/test_dynamics.c
tests_test_dynamics_CFLAGS = $(SF_TEST_CFLAGS)
tests_test_dynamics_LDADD = $(SF_TEST_LIBS)
TESTS += tests/test_run_dynamics.sh
EXTRA_DIST += tests/test_run_dynamics.sh
EXTRA_DIST += tests/bad/study_group_schedule.cfg tests/bad/study_group_schedule.expect
EXTRA_DIST += studies/snap1-dynamics.cfg studies/selffold3-dynamics.cfg docs/guides/dynamics.md
