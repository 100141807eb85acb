#!/usr/bin/env bash
# Runs every command line of a list (tests/data/bad-command-lines.txt) in a scratch folder that holds
# only cube.obj, and checks that hsr refuses each as a careless user or an attacker would want:
# exit status 1 or 2 (never a signal, never 0), within 20 s, exactly one line on stderr besides
# `hsr: warning:` lines, starting with `hsr`, and no file left behind.
#
#   bad_command_lines.sh <hsr binary> <list> <cube.obj> <scratch dir>
set -uo pipefail

if [ $# -ne 4 ]; then
    echo "usage: bad_command_lines.sh <hsr binary> <list> <cube.obj> <scratch dir>" >&2
    exit 2
fi
hsr=$(realpath "$1")
list=$(realpath "$2")
cube=$(realpath "$3")
scratch=$4

tried=0
failed=0
while IFS= read -r line; do
    [[ -z $line || $line == "#"* ]] && continue
    tried=$((tried + 1))
    rm -rf "$scratch"
    mkdir -p "$scratch"
    cp "$cube" "$scratch/cube.obj"
    eval "set -- $line"
    (cd "$scratch" && timeout -k 2 20 "$hsr" "$@" > stdout 2> stderr)
    status=$?
    mapfile -t lines < <(grep -v '^hsr: warning: ' "$scratch/stderr")
    left=$(cd "$scratch" && find . -mindepth 1 ! -name cube.obj ! -name stdout ! -name stderr | head -3 | tr '\n' ' ')
    problem=
    if [ "$status" -eq 124 ] || [ "$status" -eq 137 ]; then
        problem="timed out"
    elif [ "$status" -ge 128 ]; then
        problem="killed by signal $((status - 128))"
    elif [ "$status" -ne 1 ] && [ "$status" -ne 2 ]; then
        problem="exit status $status"
    elif [ "${#lines[@]}" -ne 1 ]; then
        problem="${#lines[@]} lines on stderr: $(head -c 300 "$scratch/stderr" | tr '\n' '|')"
    elif [[ ${lines[0]} != hsr* ]]; then
        problem="the message does not start with hsr: ${lines[0]:0:200}"
    elif [ -n "$left" ]; then
        problem="left files behind: $left"
    fi
    if [ -n "$problem" ]; then
        echo "FAILED: hsr $line: $problem"
        failed=$((failed + 1))
    fi
done < "$list"
echo "bad_command_lines: $tried command lines, $((tried - failed)) refused with one line, $failed failed"
[ "$failed" -eq 0 ] && [ "$tried" -gt 0 ]
