#!/bin/sh
# test_stab_cert with a second OpenBLAS kernel (tests/kernel2/run.sh)
exec sh "${SF_SRCDIR:-.}/tests/kernel2/run.sh" test_stab_cert
