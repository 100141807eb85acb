#!/usr/bin/env bash
# Makes every picture in docs/images/ with the commands the docs print beside it. The docs are the
# one source: in README.md and docs/**/*.md a marker line
#   <!-- picture: docs/images/NAME.png [docs/images/OTHER.svg ...] -->
#   <!-- picture (slow: WHY): docs/images/NAME.png -->
# is followed by a fenced code block whose commands make those files (a name written
# docs/images/NAME.png=MADE.png is the block's file MADE.png). Each block runs in a scratch folder
# that looks like the source folder, where `hsr` and build/hsr are HSR_BINARY, build/tests is the
# test programs beside it, and docs/images is OUT.
#   docs/images/make.sh [HSR_BINARY] [--quick] [--only NAME] [--out DIR] [--list]
#     HSR_BINARY   default build/hsr
#     --quick      leave out the blocks marked slow, naming each and why
#     --only NAME  only the blocks that make a picture whose name contains NAME
#     --out DIR    write the pictures to DIR (default docs/images)
#     --list       print each block's pictures (with "slow" or "quick") and make nothing
# It fails on a block that fails or does not make its pictures, and on a file of docs/images/ that
# no marker names.
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
binary=$src/build/hsr
out=$src/docs/images
quick=0
only=
list=0
while [ $# -gt 0 ]; do
    case $1 in
        --quick) quick=1 ;;
        --list) list=1 ;;
        --out) out=$2; shift ;;
        --only) only=$2; shift ;;
        -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "${BASH_SOURCE[0]}"; exit 0 ;;
        -*) echo "make.sh: unknown option $1" >&2; exit 2 ;;
        *) binary=$1 ;;
    esac
    shift
done
binary="$(cd "$(dirname "$binary")" && pwd)/$(basename "$binary")"
mkdir -p "$out"
out="$(cd "$out" && pwd)"
cd "$src"

# Every marked block as one record: page, line, slow reason (or -), pictures, then the block's lines.
blocks=$(mktemp -d)
scratch=$(mktemp -d)
trap 'rm -rf "$blocks" "$scratch"' EXIT
mapfile -t pages < <(echo README.md; find docs -name '*.md' | sort)
awk -v dir="$blocks" '
    FNR == 1 { pending = 0; inside = 0 }
    inside && /^[ \t]*```[ \t]*$/ { inside = 0; close(file); next }
    inside { print > file; next }
    pending && /^[ \t]*```/ { inside = 1; pending = 0; next }
    pending { printf "%s:%d: a picture marker not followed by a code block\n", FILENAME, at > "/dev/stderr"; exit 1 }
    /^<!-- picture( \(slow: [^)]*\))?: .* -->[ \t]*$/ {
        line = $0
        slow = "-"
        if (match(line, /\(slow: [^)]*\)/)) slow = substr(line, RSTART + 7, RLENGTH - 8)
        sub(/^<!-- picture[^:]*(\([^)]*\))?: /, "", line)
        sub(/ -->[ \t]*$/, "", line)
        n += 1
        file = sprintf("%s/%03d", dir, n)
        printf "%s\n%d\n%s\n%s\n", FILENAME, FNR, slow, line > (file ".head")
        close(file ".head")
        printf "" > file
        pending = 1
        at = FNR
    }
' "${pages[@]}"

# The pictures a block named are in its folder: a name=made pair is copied to its name.
check_made() {
    local work=$1 page=$2 line=$3 name want made
    shift 3
    for name in "$@"; do
        want=${name%%=*}
        made=${name#*=}
        if [ ! -e "$work/$made" ]; then
            echo "make.sh: $page:$line: the block did not make $made" >&2
            status=1
        elif [ "$made" != "$want" ]; then
            cp "$work/$made" "$work/$want"
        fi
    done
}

declare -A claimed=() ran=()
status=0
skipped=()
for head in "$blocks"/*.head; do
    body=${head%.head}
    { read -r page; read -r line; read -r slow; read -r names; } < "$head"
    read -ra made_files <<< "$names"
    for name in "${made_files[@]}"; do claimed[${name%%=*}]=1; done
    if [ "$list" = 1 ]; then
        printf '%s %s  (%s:%s)\n' "$([ "$slow" = - ] && echo quick || echo slow)" "$names" "$page" "$line"
        continue
    fi
    [ -z "$only" ] || [[ "$names" == *"$only"* ]] || continue
    if [ "$quick" = 1 ] && [ "$slow" != - ]; then
        skipped+=("$names: $slow ($page:$line)")
        continue
    fi
    # A block shown on two pages is run once.
    key=$(md5sum < "$body")
    if [ -n "${ran[$key]:-}" ]; then
        work=${ran[$key]}
        echo "make.sh: $names ($page:$line): made by the same block before"
        [ -f "$work.failed" ] && continue
        check_made "$work" "$page" "$line" "${made_files[@]}"
        continue
    fi
    work="$scratch/$(basename "$body")"
    ran[$key]=$work
    mkdir -p "$work/docs" "$work/build" "$work/bin"
    for entry in "$src"/* "$src"/.[!.]*; do
        [ -e "$entry" ] || continue
        case $(basename "$entry") in docs|build|.git) continue ;; esac
        ln -s "$entry" "$work/$(basename "$entry")"
    done
    for entry in "$src"/docs/*; do
        [ "$(basename "$entry")" = images ] || ln -s "$entry" "$work/docs/$(basename "$entry")"
    done
    ln -s "$out" "$work/docs/images"
    ln -s "$binary" "$work/build/hsr"
    ln -s "$binary" "$work/bin/hsr"
    ln -s "$(dirname "$binary")/tests" "$work/build/tests"
    echo "make.sh: $names ($page:$line)"
    if ! (cd "$work" && PATH="$work/bin:$PATH" bash -euo pipefail "$body" > "$work.log" 2>&1); then
        echo "make.sh: $page:$line: the block failed:" >&2
        sed 's/^/    /' "$work.log" >&2
        status=1
        touch "$work.failed"
        continue
    fi
    check_made "$work" "$page" "$line" "${made_files[@]}"
done

for file in docs/images/*; do
    case $file in docs/images/make.sh) continue ;; esac
    [ -n "${claimed[$file]:-}" ] || { echo "make.sh: no picture marker in the docs names $file" >&2; status=1; }
done
for reason in "${skipped[@]}"; do echo "make.sh: skipped (slow) $reason"; done
exit $status
