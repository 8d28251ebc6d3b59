#!/bin/sh
# test_start.sh with a second OpenBLAS kernel (tests/kernel2/run.sh)
exec sh "${SF_SRCDIR:-.}/tests/kernel2/run.sh" test_start.sh
