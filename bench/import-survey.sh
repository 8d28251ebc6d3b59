#!/bin/sh
# import-survey.sh - every FOLD and SVG file under DIR through `smoothfold
# import`, and again with the option its message names (--piece=N is
# tried as --piece=1): the table of docs/guides/importing-patterns.md
# ("Files from the design tools").
#
#   sh bench/import-survey.sh DIR [OUT.tsv]
#
# DIR holds the repositories unpacked, one folder each (for example from
# `git archive` of Origami Simulator, Rabbit Ear, robbykraft/Origami and
# flat-folder at the commits tests/public/README.md names).  OUT.tsv (default
# survey.tsv) gets one line per file: status, status with the option,
# the option, the file, the message.  About 2 minutes for the 984 files.
set -u
dir=${1:?usage: sh bench/import-survey.sh DIR [OUT.tsv]}
out=${2:-survey.tsv}
bin=${SMOOTHFOLD:-$(dirname "$0")/../src/smoothfold}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
( cd "$dir" && find . \( -name '*.fold' -o -name '*.svg' \) | sort ) > "$tmp/files"
: > "$out"
while read -r f; do
    timeout 120 "$bin" import "$dir/$f" -o "$tmp/s.cfg" >/dev/null 2>"$tmp/e"; rc=$?
    msg=$(tail -1 "$tmp/e"); opt=-; rc2=-
    if [ $rc -ne 0 ]; then
        opt=$(printf '%s' "$msg" | grep -o -- '--[a-z-]*\(=[a-z0-9.]*\)\?' |
              grep -v -- '--set\|--size\|--unit\|--frame' | head -1 | sed 's/^--piece=$/--piece=1/')
        [ -n "$opt" ] || opt=-
        if [ "$opt" != - ]; then
            timeout 120 "$bin" import "$dir/$f" $opt -o "$tmp/s.cfg" >/dev/null 2>/dev/null; rc2=$?
        fi
    fi
    printf '%s\t%s\t%s\t%s\t%s\n' "$rc" "$rc2" "$opt" "$f" "$msg" >> "$out"
done < "$tmp/files"
printf 'repository\tfiles\tas they are\twith the option\trefused\n'
awk -F'\t' '{ split($4, a, "/"); r = a[2]; n[r]++; if ($1 == 0) ok[r]++; else if ($2 == 0) opt[r]++; else bad[r]++ }
    END { for (r in n) { printf "%s\t%d\t%d\t%d\t%d\n", r, n[r], ok[r], opt[r], bad[r]; N += n[r]; O += ok[r]; P += opt[r]; B += bad[r] }
          printf "all\t%d\t%d\t%d\t%d\n", N, O, P, B }' "$out"
