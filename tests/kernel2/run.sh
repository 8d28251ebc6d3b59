#!/bin/sh
# tests/kernel2/run.sh TEST - run TEST (a script of tests/, or a test
# program) again with another OpenBLAS kernel than the environment's:
# Prescott (SSE3; the kernel furthest from the AVX2 and AVX-512 ones a
# modern CPU picks), or Haswell where the environment already names
# Prescott.  The numerical tests of the start, stability and bifurcation
# run twice in `make check`, so that an answer that depends on rounding
# fails there, not only on another machine.  TAP passes through.
t=${1:?usage: run.sh TEST}
case "${OPENBLAS_CORETYPE:-}" in
    [Pp][Rr][Ee][Ss][Cc][Oo][Tt][Tt]) k=Haswell ;;
    *) k=Prescott ;;
esac
OPENBLAS_CORETYPE=$k
export OPENBLAS_CORETYPE
echo "# $t with OPENBLAS_CORETYPE=$k"
case $t in
    *.sh) exec sh "${SF_SRCDIR:-.}/tests/$t" ;;
    *) exec "${SF_BUILDDIR:-.}/tests/$t" ;;
esac
