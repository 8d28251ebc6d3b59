#!/bin/sh
# test_sstab with a second OpenBLAS kernel (tests/kernel2/run.sh)
exec sh "${SF_SRCDIR:-.}/tests/kernel2/run.sh" test_sstab
