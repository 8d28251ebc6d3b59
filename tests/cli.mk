# tests/cli.mk: the command line, output directories and run comparison
# (issue 14), all shell scripts speaking TAP.
TESTS += tests/test_cli.sh tests/test_outdir.sh tests/test_cmp_runs.sh tests/test_plots.sh \
	tests/test_set_types.sh tests/test_run_honest.sh tests/test_progress.sh
EXTRA_DIST += tests/test_cli.sh tests/test_outdir.sh tests/test_cmp_runs.sh tests/test_plots.sh \
	tests/test_set_types.sh tests/test_run_honest.sh tests/test_progress.sh \
	tests/fuzz/fuzz_study.c tests/fuzz/run.sh tests/fuzz/lsan.supp \
	tests/bad/fixed_on_vertex.cfg tests/bad/fixed_on_vertex.expect
