#!/bin/bash
# test_completion.sh - the bash completion (src/cli/completion/smoothfold)
# offers the commands, a command's options, the study keys after --set and
# --vary, and the values a string key allows, all asked of the binary.
# Driven as bash drives it: COMP_WORDS split at '=' as COMP_WORDBREAKS does.
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
. "$src/tests/tap.sh"
. "$src/src/cli/completion/smoothfold"
echo "1..9"
# complete WORD... : the words as bash passes them, the last one being completed
complete_words() {
    COMP_WORDS=("$bin" "$@")
    COMP_CWORD=$((${#COMP_WORDS[@]} - 1))
    COMPREPLY=()
    _smoothfold
    printf '%s\n' "${COMPREPLY[@]}"
}
has() { printf '%s\n' "$1" | grep -qx -- "$2"; }
r=$(complete_words "")
if has "$r" run && has "$r" import && has "$r" sweep && has "$r" keys && has "$r" check; then
    ok "commands: $(echo $r)"
else nok "commands: $(echo $r)"; fi
r=$(complete_words "im")
[ "$r" = import ] && ok "'im' completes to import" || nok "'im': $r"
r=$(complete_words run studies/strip3.cfg "--")
if has "$r" --set && has "$r" --force && has "$r" --plot && has "$r" --no-plot; then ok "run's options: $(echo $r)"
else nok "run's options: $(echo $r)"; fi
r=$(complete_words run studies/strip3.cfg --set "solver.con")
[ "$r" = "solver.constraints=" ] && ok "--set solver.con -> solver.constraints=" || nok "--set solver.con: $r"
r=$(complete_words run s.cfg --set "analysis.")
if has "$r" analysis.type= && has "$r" analysis.branch_depth= && has "$r" analysis.flat_angle= &&
   ! printf '%s' "$r" | grep -q '\[\]'; then
    ok "--set analysis. offers the analysis keys ($(echo "$r" | wc -l)), no list patterns"
else nok "--set analysis.: $(echo $r)"; fi
# every key offered is one the reference manual documents (test_study.c
# checks the other way: every schema key is in the manual)
bad=""; nk=0
for k in $(complete_words run s.cfg --set ""); do
    nk=$((nk + 1))
    grep -qF -- "\`${k%=}\`" "$src/docs/reference/study-keys.md" || bad="$bad ${k%=}"
done
[ $nk -gt 50 ] && [ -z "$bad" ] && ok "all $nk keys offered are documented in docs/reference/study-keys.md" ||
    nok "keys offered ($nk) not in docs/reference/study-keys.md:$bad"
# keys lists values, not the groups that hold them
if "$bin" keys | grep -qx solver.tolerance && ! "$bin" keys | grep -qx solver && ! "$bin" keys | grep -qx 'folds\[\]'; then
    ok "smoothfold keys lists leaf keys (solver.tolerance), not groups (solver, folds[])"
else nok "smoothfold keys lists groups or misses solver.tolerance"; fi
r=$(complete_words run s.cfg --set solver.constraints = "")
if has "$r" exact && has "$r" penalty; then ok "--set solver.constraints= offers $(echo $r)"
else nok "values of solver.constraints: $(echo $r)"; fi
r=$(complete_words sweep s.cfg --vary analysis.type = "dyn")
[ "$r" = dynamics ] && ok "--vary analysis.type=dyn -> dynamics" || nok "--vary analysis.type=dyn: $r"
