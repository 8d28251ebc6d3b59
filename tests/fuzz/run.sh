#!/bin/sh
# run.sh SECONDS [TARGET...] - build the libFuzzer targets (clang
# -fsanitize=fuzzer,address,undefined) and run each for SECONDS:
#   study  the study reader, topology and model construction (fuzz_study.c),
#          seeded from studies/*.cfg and tests/bad/*.cfg;
#   fold   the FOLD reader and the study it writes (fuzz_import.c), seeded
#          from tests/fold, tests/bad/fold_* and the public FOLD files of
#          tests/public;
#   svg    the SVG reader (fuzz_import.c -DSF_FUZZ_SVG=1), seeded from
#          tests/bad/svg_* and the public SVG files of tests/public.
# Default: all three.
#
# Output is TAP, one test per target: "ok N" when the run ends without a
# crash, leak, sanitizer report or time-out, with the number of
# executions; "ok N # SKIP" when clang (or its libFuzzer runtime) is not
# installed.  Environment: SF_SRCDIR (source tree), SF_FUZZ_DIR (work
# directory, kept: corpora, logs, crash files; default a temporary one,
# removed afterwards).
secs=${1:-60}
shift
targets=${*:-study fold svg}
src=${SF_SRCDIR:-$(cd "$(dirname "$0")/../.." && pwd)}
n=0; for t in $targets; do n=$((n + 1)); done
echo "1..$n"
if ! command -v clang >/dev/null 2>&1; then
    i=0; for t in $targets; do i=$((i + 1)); echo "ok $i # SKIP clang is not installed (apt-get install clang)"; done; exit 0
fi
keep=${SF_FUZZ_DIR:+1}
work=${SF_FUZZ_DIR:-$(mktemp -d)}
mkdir -p "$work/obj"
[ -n "$keep" ] || trap 'rm -rf "$work"' EXIT
# the library sources the targets reach (globs: new files are picked up)
inc="-I$src/src -I$src/src/pattern -I$src/src/model -I$src/src/io"
pc=$(pkg-config --cflags libconfig jansson libxml-2.0 2>/dev/null)
flags="-std=c11 -D_DEFAULT_SOURCE -D_POSIX_C_SOURCE=200809L -g -O1 -fsanitize=fuzzer-no-link,address,undefined $pc"
libs="$(pkg-config --libs libconfig jansson libxml-2.0 2>/dev/null || echo -lconfig -ljansson -lxml2) -llapack -lblas -lm"
objs=""
for c in "$src"/src/sf_error.c "$src"/src/pattern/*.c "$src"/src/model/*.c "$src"/src/io/outbuf.c; do
    o="$work/obj/$(basename "$c" .c).o"
    if ! clang $flags $inc -c "$c" -o "$o" 2>"$work/build.log"; then
        i=0; for t in $targets; do i=$((i + 1)); echo "not ok $i - fuzz $t: cannot compile $c"; done
        sed 's/^/#   /' "$work/build.log" | head -20; exit 0
    fi
    objs="$objs $o"
done
LSAN_OPTIONS="suppressions=$src/tests/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"; export LSAN_OPTIONS
i=0
for t in $targets; do
    i=$((i + 1))
    case $t in
        study) main="$src/tests/fuzz/fuzz_study.c"; def=""; maxlen=16384;;
        fold)  main="$src/tests/fuzz/fuzz_import.c"; def="-DSF_FUZZ_SVG=0"; maxlen=16384;;
        svg)   main="$src/tests/fuzz/fuzz_import.c"; def="-DSF_FUZZ_SVG=1"; maxlen=16384;;
        *) echo "not ok $i - unknown fuzz target '$t' (study, fold, svg)"; continue;;
    esac
    exe="$work/fuzz_$t"
    if ! clang $flags $def -fsanitize=fuzzer,address,undefined $inc "$main" $objs $libs -o "$exe" 2>"$work/build.log"; then
        if grep -q "libclang_rt.fuzzer\|fuzzer.*not found\|cannot find.*fuzzer" "$work/build.log"; then
            echo "ok $i # SKIP clang has no libFuzzer runtime"; continue
        fi
        echo "not ok $i - fuzz $t: cannot link"; sed 's/^/#   /' "$work/build.log" | head -20; continue
    fi
    seeds="$work/seeds-$t"; corpus="$work/corpus-$t"
    mkdir -p "$seeds" "$corpus"
    case $t in
        study) cp "$src"/studies/*.cfg "$src"/tests/bad/*.cfg "$seeds/";;
        fold)  find "$src/tests/fold" "$src/tests/bad" "$src/tests/public" -name '*.fold' -size -16k \
                   -exec sh -c 'cp "$1" "$2/$(echo "$1" | md5sum | cut -c1-12).fold"' _ {} "$seeds" \; 2>/dev/null;;
        svg)   find "$src/tests/bad" "$src/tests/public" -name '*.svg' -size -16k \
                   -exec sh -c 'cp "$1" "$2/$(echo "$1" | md5sum | cut -c1-12).svg"' _ {} "$seeds" \; 2>/dev/null;;
    esac
    log="$work/fuzz-$t.log"
    (cd "$work" && "$exe" -max_total_time="$secs" -timeout=20 -rss_limit_mb=2048 -max_len=$maxlen \
        -print_final_stats=1 -artifact_prefix="$work/$t-" "$corpus" "$seeds" >"$log" 2>&1)
    rc=$?
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    if [ $rc -eq 0 ]; then
        echo "ok $i - fuzz_$t: ${execs:-?} executions in ${secs} s, no crash"
    else
        echo "not ok $i - fuzz_$t: status $rc after ${execs:-?} executions"
        grep -E "ERROR|SUMMARY|fuzz_(study|import):|Test unit written" "$log" | head -10 | sed 's/^/#   /'
        [ -n "$keep" ] || for a in "$work/$t"-crash-* "$work/$t"-leak-* "$work/$t"-timeout-*; do
            [ -f "$a" ] && { echo "#   input:"; od -c "$a" | head -20 | sed 's/^/#   /'; }
        done
    fi
done
