# the numerical tests of the start, stability and bifurcation once more,
# with a second OpenBLAS kernel (tests/kernel2/run.sh)
SF_KERNEL2_TESTS = tests/kernel2/test_start.sh tests/kernel2/test_flatstart.sh \
	tests/kernel2/test_flatstart_sparse.sh tests/kernel2/test_stab_inertia.sh \
	tests/kernel2/test_run_exact.sh tests/kernel2/test_stab_cert.sh \
	tests/kernel2/test_bifurcation.sh tests/kernel2/test_paths.sh tests/kernel2/test_sstab.sh
TESTS += $(SF_KERNEL2_TESTS)
EXTRA_DIST += $(SF_KERNEL2_TESTS) tests/kernel2/run.sh
