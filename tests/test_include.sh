#!/bin/sh
# test_include.sh - a study's @include reads files in the study's folder
# only (src/pattern/study_include.c): "../" and a symbolic link out of it
# are refused with one line naming the line and the folder, an absolute
# path is taken inside the folder (libconfig's include_dir), and
# --allow-include=DIR admits DIR.  TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
. "$src/tests/tap.sh"
echo "1..5"
mkdir -p "$tmp/study/parts" "$tmp/other"
sed '/^solver *=/,$d' "$src/studies/fold1-buckle.cfg" > "$tmp/study/head.cfg"
sed -n '/^solver *=/,$p' "$src/studies/fold1-buckle.cfg" > "$tmp/study/parts/tail.cfg"
cp "$tmp/study/parts/tail.cfg" "$tmp/other/tail.cfg"
{ cat "$tmp/study/head.cfg"; echo '@include "parts/tail.cfg"'; } > "$tmp/study/in.cfg"
if "$bin" check "$tmp/study/in.cfg" >/dev/null 2>"$tmp/err"; then ok "an include inside the folder is read"
else nok "an include inside the folder is read"; sed 's/^/#   /' "$tmp/err"; fi
{ cat "$tmp/study/head.cfg"; echo '@include "../other/tail.cfg"'; } > "$tmp/study/up.cfg"
line=$(grep -n '@include' "$tmp/study/up.cfg" | cut -d: -f1)
out=$("$bin" check "$tmp/study/up.cfg" 2>&1 >/dev/null); rc=$?
case "$rc:$out" in 1:*"up.cfg:$line: @include \"../other/tail.cfg\": "*"/other/tail.cfg is outside the study's folder "*"--allow-include=DIR"*)
    [ "$(printf '%s\n' "$out" | wc -l)" -eq 1 ] && ok "../ out of the folder: refused in one line" || nok "../: more than one line";;
    *) nok "../ out of the folder refused ($rc: $out)";; esac
ln -s "$tmp/other/tail.cfg" "$tmp/study/link.cfg"
{ cat "$tmp/study/head.cfg"; echo '@include "link.cfg"'; } > "$tmp/study/ln.cfg"
out=$("$bin" check "$tmp/study/ln.cfg" 2>&1 >/dev/null); rc=$?
case "$rc:$out" in 1:*"is outside the study's folder"*) ok "a symbolic link out of the folder: refused";;
    *) nok "a symbolic link out of the folder ($rc: $out)";; esac
if "$bin" check "$tmp/study/up.cfg" --allow-include="$tmp/other" >/dev/null 2>"$tmp/err"; then ok "--allow-include=DIR admits DIR"
else nok "--allow-include=DIR admits DIR"; sed 's/^/#   /' "$tmp/err"; fi
{ cat "$tmp/study/head.cfg"; echo '@include "/etc/passwd"'; } > "$tmp/study/abs.cfg"
out=$("$bin" check "$tmp/study/abs.cfg" 2>&1 >/dev/null); rc=$?
case "$rc:$out" in 1:*"abs.cfg:"*"cannot open include file"*) ok "an absolute path is looked for inside the folder (/etc/passwd not read)";;
    *) nok "an absolute path ($rc: $out)";; esac
