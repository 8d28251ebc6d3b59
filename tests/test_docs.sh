#!/bin/sh
# test_docs.sh - the documentation as a user meets it.  Every fenced block
# marked ```sh doc-test in README.md and docs/ is run as written, in order,
# one working directory per file (with the repository's studies/ beside it
# and the built smoothfold first on PATH), under `set -e`: each command must
# exit 0.  Every relative link of README.md and docs/ must name a file that
# exists (and a heading of it, for #anchors), README.md stays under 200
# lines and each doc at most 500.  Output is TAP.
#
# The blocks are meant to run on small sheets in seconds; a guide whose
# commands need long runs shows them in a plain block instead.
src=${SF_SRCDIR:-$(dirname "$0")/..}
. "$src/tests/tap.sh"
bindir=$(cd "$(dirname "$bin")" && pwd)
docs=$(cd "$src" && { echo README.md; find docs -name '*.md' | sort; })

# --- the commands of the guides -------------------------------------------
mkdir -p "$tmp/blocks"
for f in $docs; do
    awk -v f="$f" -v out="$tmp/blocks" '
        /^```sh doc-test[ \t]*$/ { n++; inb = 1; name = sprintf("%s/%s.%03d", out, f, NR);
            gsub("/", "_", name); name = out "/" substr(name, length(out) + 2);
            print "# " f ":" NR > name; next }
        inb && /^```/ { inb = 0; close(name); next }
        inb { print > name }' "$src/$f"
done
for b in $(ls "$tmp/blocks" | sort); do
    where=$(head -1 "$tmp/blocks/$b" | sed 's/^# //')
    file=${where%:*}
    wd="$tmp/work/$(echo "$file" | tr '/' '_')"
    if [ ! -d "$wd" ]; then mkdir -p "$wd"; ln -s "$src/studies" "$wd/studies"; fi
    ncmd=$(grep -cv '^[[:space:]]*\(#.*\)\?$' "$tmp/blocks/$b")
    if (cd "$wd" && PATH="$bindir:$PATH" sh -e "$tmp/blocks/$b") >"$tmp/out" 2>&1; then
        ok "$where: the block's $ncmd lines run, every command exits 0"
    else
        nok "$where: a command of the block failed"
        tail -5 "$tmp/out" | sed 's/^/#   /'
    fi
done
nblocks=$(ls "$tmp/blocks" | wc -l)
[ "$nblocks" -ge 5 ] && ok "$nblocks doc-test blocks found" || nok "only $nblocks doc-test blocks found"

# --- links -----------------------------------------------------------------
# slug of a heading as GitHub makes it: lower case, punctuation dropped,
# spaces to hyphens
slugs() {
    awk '/^```/ { code = !code; next } !code && /^#+ / { sub(/^#+ +/, ""); print }' "$1" |
        tr 'A-Z' 'a-z' | sed 's/[^a-z0-9 _-]//g; s/ /-/g'
}
bad=""; nlinks=0
for f in $docs; do
    dir=$(dirname "$f")
    # the targets of ](...) outside code (fenced blocks and `spans`)
    for t in $(awk '/^```/ { code = !code; next } !code { gsub(/`[^`]*`/, ""); print }' "$src/$f" |
               grep -o '](\([^)# ]*\)\(#[^) ]*\)\?)' | sed 's/^](//; s/)$//'); do
        case $t in http://*|https://*|mailto:*) continue;; esac
        nlinks=$((nlinks + 1))
        path=${t%%#*}; anchor=""
        case $t in *'#'*) anchor=${t#*#};; esac
        if [ -z "$path" ]; then target="$src/$f"; else target="$src/$dir/$path"; fi
        if [ ! -e "$target" ]; then
            bad="$bad $f:($t)"; continue
        fi
        if [ -n "$anchor" ] && [ -f "$target" ]; then
            slugs "$target" | grep -qx -- "$anchor" || bad="$bad $f:($t)"
        fi
    done
done
if [ -z "$bad" ] && [ $nlinks -gt 50 ]; then ok "all $nlinks relative links of README.md and docs/ resolve"
else nok "$nlinks links, broken:$bad"; fi

# --- length ----------------------------------------------------------------
long=""
n=$(wc -l <"$src/README.md"); [ "$n" -lt 200 ] || long="$long README.md:$n"
for f in $docs; do
    [ "$f" = README.md ] && continue
    n=$(wc -l <"$src/$f"); [ "$n" -le 500 ] || long="$long $f:$n"
done
[ -z "$long" ] && ok "README.md under 200 lines, every doc at most 500" || nok "too long:$long"
echo "1..$i"
