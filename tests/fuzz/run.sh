#!/bin/sh
# run.sh SECONDS [JOBS] - build the libFuzzer target fuzz_study (the study
# reader, topology and model construction, compiled with
# clang -fsanitize=fuzzer,address,undefined) and run it for SECONDS on a
# corpus seeded from studies/*.cfg and tests/bad/*.cfg.
#
# Output is TAP (one test): "ok 1" when the run ends without a crash, leak,
# sanitizer report or time-out, with the number of executions; "ok 1 # SKIP"
# when clang (or its libFuzzer runtime) is not installed.
# Environment: SF_SRCDIR (source tree), SF_FUZZ_DIR (work directory, kept:
# corpus, log, crash files; default a temporary one, removed afterwards).
secs=${1:-60}
src=${SF_SRCDIR:-$(cd "$(dirname "$0")/../.." && pwd)}
echo "1..1"
if ! command -v clang >/dev/null 2>&1; then
    echo "ok 1 # SKIP clang is not installed (apt-get install clang)"; exit 0
fi
keep=${SF_FUZZ_DIR:+1}
work=${SF_FUZZ_DIR:-$(mktemp -d)}
mkdir -p "$work/corpus" "$work/seeds" "$work/obj"
[ -n "$keep" ] || trap 'rm -rf "$work"' EXIT
# the library sources the target reaches (globs: new files are picked up)
inc="-I$src/src -I$src/src/pattern -I$src/src/model -I$src/src/analysis -I$src/src/io"
flags="-std=c11 -D_DEFAULT_SOURCE -D_POSIX_C_SOURCE=200809L -g -O1 -fsanitize=fuzzer-no-link,address,undefined $(pkg-config --cflags libconfig jansson 2>/dev/null)"
objs=""
for c in "$src"/src/sf_error.c "$src"/src/pattern/*.c "$src"/src/model/*.c "$src"/src/io/outbuf.c; do
    o="$work/obj/$(basename "$c" .c).o"
    if ! clang $flags $inc -c "$c" -o "$o" 2>"$work/build.log"; then
        echo "not ok 1 - fuzz: cannot compile $c"; sed 's/^/#   /' "$work/build.log" | head -20; exit 0
    fi
    objs="$objs $o"
done
if ! clang $flags -fsanitize=fuzzer,address,undefined $inc "$src/tests/fuzz/fuzz_study.c" $objs \
        $(pkg-config --libs libconfig 2>/dev/null || echo -lconfig) \
        $(pkg-config --libs jansson 2>/dev/null || echo -ljansson) -llapack -lblas -lm \
        -o "$work/fuzz_study" 2>"$work/build.log"; then
    if grep -q "libclang_rt.fuzzer\|fuzzer.*not found\|cannot find.*fuzzer" "$work/build.log"; then
        echo "ok 1 # SKIP clang has no libFuzzer runtime"; exit 0
    fi
    echo "not ok 1 - fuzz: cannot link"; sed 's/^/#   /' "$work/build.log" | head -20; exit 0
fi
cp "$src"/studies/*.cfg "$src"/tests/bad/*.cfg "$work/seeds/"
cd "$work" || exit 1
LSAN_OPTIONS="suppressions=$src/tests/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"; export LSAN_OPTIONS
./fuzz_study -max_total_time="$secs" -timeout=20 -rss_limit_mb=2048 -max_len=16384 \
    -print_final_stats=1 -artifact_prefix="$work/" corpus seeds >"$work/fuzz.log" 2>&1
rc=$?
execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/fuzz.log" | tail -1)
if [ $rc -eq 0 ]; then
    echo "ok 1 - fuzz_study: ${execs:-?} executions in ${secs} s, no crash"
else
    echo "not ok 1 - fuzz_study: status $rc after ${execs:-?} executions"
    grep -E "ERROR|SUMMARY|fuzz_study:|Test unit written" "$work/fuzz.log" | head -10 | sed 's/^/#   /'
    [ -n "$keep" ] || for a in "$work"/crash-* "$work"/leak-* "$work"/timeout-*; do
        [ -f "$a" ] && { echo "#   input:"; od -c "$a" | head -20 | sed 's/^/#   /'; }
    done
fi
