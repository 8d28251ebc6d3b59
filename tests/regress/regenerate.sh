#!/bin/sh
# regenerate.sh - rewrite the stored results tests/regress/STUDY.csv that
# tests/test_regress.sh compares every study with.  Run it only when a
# change of results is intended (and say why in the commit):
#     tests/regress/regenerate.sh BUILDDIR [STUDY...]
# Each file holds the study's path at fixed parameter values, solved at
# those values (tests/regress/sample.sh), with the default settings of the
# study file.
set -e
src=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:?usage: regenerate.sh BUILDDIR [STUDY...]}
shift
studies=${*:-"strip3 fold1 waterbomb2 square4 square4-stiff square4-narrow square4-corner square4-irregular fold1-buckle snap1 square4-inplane hard-near-pi hard-stiff-ratio hard-tiny-width"}
rev=$(git -C "$src" rev-parse --short HEAD 2>/dev/null || echo unknown)
for s in $studies; do
    "$src/tests/regress/sample.sh" "$build/src/smoothfold" "$src/studies/$s.cfg" "$src/tests/regress/$s.csv" "git $rev"
    echo "tests/regress/$s.csv: $(grep -vc '^#' "$src/tests/regress/$s.csv") lines"
done
