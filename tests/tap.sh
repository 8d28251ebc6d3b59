# tap.sh - sourced by the shell tests (after setting src): the binary
# under test, a temporary directory removed on exit, and numbered TAP
# lines (ok / nok; the plan line stays in each test).
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
i=0
ok() { i=$((i + 1)); echo "ok $i - $1"; }
nok() { i=$((i + 1)); echo "not ok $i - $1"; }
