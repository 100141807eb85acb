#!/usr/bin/env bash
# Renders every regular file of a model corpus (Debian's assimp-testmodels, fetched by
# models/fetch-models.sh) with `hsr render` and checks that each one either renders or is refused
# with one line, within 10 s and 1 GB:
#   rendered  exit 0, a 128x128 PNG written, and nothing on stderr but warnings
#   refused   exit 1..127, exactly one line on stderr starting with `hsr:` besides warnings
#             (`hsr: warning: ...`), no picture and no temporary file left, and not a refusal for
#             lack of memory
# Anything else (a signal, a timeout, over 1 GB of peak RSS, several lines or none, exit 0 without a
# picture) fails the test, naming the file and what happened. Files of the formats hsr reads (OBJ,
# OFF, PLY, STL, glTF) are also tried altered: renamed (without an extension, with the extension
# upper-case, with the extension of another of those formats) and cut off at half their size. The
# files that render are drawn again by the hidden-line plugins roberts and appel, with at most
# 20,000 stored triangles so that a big mesh is refused at once rather than drawn for minutes.
# Ends with a summary for each run: files tried, rendered, refused by kind of message, the slowest
# file and the largest peak RSS.
#
#   model_corpus.sh [--no-altered] <hsr binary> <corpus dir> <scratch dir>
#
# --no-altered leaves out the renamed and cut copies (for a corpus that is already made of altered
# files, such as tests/mutated_inputs.sh's).
#
# Peak RSS is measured by GNU time (%M); `prlimit --as` caps the address space at 4 GB as a safety
# net, so this is a test for the normal build (AddressSanitizer reserves far more address space).
set -uo pipefail

alter=yes
if [ "${1:-}" = --no-altered ]; then
    alter=no
    shift
fi
if [ $# -ne 3 ]; then
    echo "usage: model_corpus.sh [--no-altered] <hsr binary> <corpus dir> <scratch dir>" >&2
    exit 2
fi
hsr=$(realpath "$1")
corpus=$2
scratch=$3

if [ ! -d "$corpus" ]; then
    echo "model_corpus: models not fetched: run models/fetch-models.sh ($corpus is missing)"
    exit 0
fi
for tool in /usr/bin/time prlimit timeout; do
    if ! command -v "$tool" > /dev/null; then
        echo "model_corpus: $tool is missing (bash setup.sh installs it)" >&2
        exit 1
    fi
done

readonly seconds_allowed=10
readonly rss_allowed_kb=$((1024 * 1024))
readonly address_space_cap=$((4 * 1024 * 1024 * 1024))
readonly line_triangle_cap=20000

rm -rf "$scratch"
mkdir -p "$scratch/altered" "$scratch/runs"

# One render of `file` with the extra hsr arguments after it; writes one record to `record`:
#   verdict <TAB> seconds <TAB> peak RSS in KB <TAB> file <TAB> detail
# where verdict is rendered, refused or FAILED, and detail is the message or what went wrong.
render_one() {
    local record=$1 file=$2
    shift 2
    local out=$record.png err=$record.err rss_file=$record.rss
    local start=${EPOCHREALTIME/./}
    prlimit --as="$address_space_cap" -- /usr/bin/time -f %M -o "$rss_file" \
        timeout -k 2 "$seconds_allowed" "$hsr" render "$file" --width 128 --height 128 "$@" -o "$out" \
        > "$record.stdout" 2> "$err"
    local status=$?
    local microseconds=$((${EPOCHREALTIME/./} - start))
    local rss_lines rss=0
    mapfile -t rss_lines < "$rss_file"
    [ ${#rss_lines[@]} -gt 0 ] && [[ ${rss_lines[-1]} =~ ^[0-9]+$ ]] && rss=${rss_lines[-1]}
    # Warnings (`hsr: warning: ...`) may come before the one error line, or with a picture and
    # hsr's `wrote FILE (...)`.
    local line err_lines=()
    while IFS= read -r line || [ -n "$line" ]; do
        [[ $line == "hsr: warning: "* ]] || { [ "$status" -eq 0 ] && [[ $line == "wrote $out "* ]]; } ||
            err_lines+=("$line")
    done < "$err"
    local lines=${#err_lines[@]}
    local message=${err_lines[0]:-}
    message=${message:0:300}

    local verdict=FAILED detail
    if [ "$status" -eq 124 ] || [ "$status" -eq 137 ]; then
        detail="timed out after ${seconds_allowed} s"
    elif [ "$status" -ge 128 ]; then
        detail="killed by signal $((status - 128)) ($(kill -l $((status - 128)) 2> /dev/null))"
    elif [ "$rss" -gt "$rss_allowed_kb" ]; then
        detail="peak RSS $((rss / 1024)) MB is over 1 GB"
    elif [ "$status" -eq 0 ] && [ "$lines" -ne 0 ]; then
        detail="exit 0 with $lines lines on stderr that are not warnings: ${message}"
    elif [ "$status" -eq 0 ]; then
        # The signature, then IHDR's length and type, then width and height (big-endian).
        local header
        header=$(od -An -tx1 -N 24 "$out" 2> /dev/null)
        header=${header//[$' \n']/}
        if [ "${header:0:16}" != 89504e470d0a1a0a ]; then
            detail="exit 0 without a PNG"
        elif [ "${header:32:16}" != 0000008000000080 ]; then
            detail="exit 0 with a PNG that is not 128x128 (IHDR: ${header:32:16})"
        else
            verdict=rendered
            detail=
        fi
    elif [ "$lines" -ne 1 ]; then
        local shown="${err_lines[*]:0:3}"
        detail="exit $status with $lines lines on stderr besides warnings: ${shown:0:300}"
    elif [[ $message != hsr:* ]]; then
        detail="exit $status with a message not starting with hsr: $message"
    elif [ -e "$out" ] || compgen -G "${out%/*}/.${out##*/}.tmp-*" > /dev/null; then
        detail="exit $status but a picture or temporary file was left: $message"
    elif [[ $message == *"not enough memory"* ]]; then
        detail="ran out of address space ($((address_space_cap >> 30)) GB): $message"
    else
        verdict=refused
        detail=$message
    fi
    printf '%s\t%d.%02d\t%s\t%s\t%s\n' "$verdict" $((microseconds / 1000000)) $((microseconds / 10000 % 100)) \
        "$rss" "$file" "$detail" > "$record"
    rm -f "$out" "$err" "$rss_file" "$record.stdout"
}
export -f render_one
export hsr seconds_allowed rss_allowed_kb address_space_cap

# Runs `render_one` over the NUL-separated files on stdin, two at a time, with the extra hsr
# arguments; records go to $scratch/runs/<run>/<n>.
run_corpus() {
    local run=$1
    shift
    mkdir -p "$scratch/runs/$run"
    local n=0
    while IFS= read -r -d '' file; do
        n=$((n + 1))
        printf '%s\0%s\0' "$scratch/runs/$run/$n" "$file"
    done | xargs -0 -r -n 2 -P 2 bash -c 'render_one "$@" '"${*@Q}" _
}

# The corpus, and the files of the formats hsr reads renamed and cut.
corpus_list=$scratch/corpus.list
find "$corpus" -type f -print0 | sort -z > "$corpus_list"
if [ ! -s "$corpus_list" ]; then
    echo "model_corpus: $corpus holds no files" >&2
    exit 1
fi
altered_list=$scratch/altered.list
: > "$altered_list"
declare -A wrong_extension=([obj]=ply [ply]=stl [stl]=off [off]=obj [gltf]=glb [glb]=gltf)
n=0
while IFS= read -r -d '' file; do
    base=$(basename "$file")
    extension=${base##*.}
    extension=${extension,,}
    [ "$alter" = yes ] && [ -n "${wrong_extension[$extension]:-}" ] || continue
    n=$((n + 1))
    stem=${base%.*}
    mkdir -p "$scratch/altered/$n"
    for name in "$stem" "$stem.${extension^^}" "$stem.${wrong_extension[$extension]}"; do
        cp "$file" "$scratch/altered/$n/$name"
        printf '%s\0' "$scratch/altered/$n/$name" >> "$altered_list"
    done
    size=$(stat -c %s "$file")
    head -c $((size / 2)) "$file" > "$scratch/altered/$n/cut-$base"
    printf '%s\0' "$scratch/altered/$n/cut-$base" >> "$altered_list"
done < "$corpus_list"

start=$EPOCHREALTIME
run_corpus surface < "$corpus_list"
run_corpus altered < "$altered_list"
rendered_list=$scratch/rendered.list
cat "$scratch"/runs/surface/* | awk -F '\t' '$1 == "rendered" { printf "%s%c", $4, 0 }' > "$rendered_list"
run_corpus roberts -a roberts --limit stored-triangles=$line_triangle_cap < "$rendered_list"
run_corpus appel -a appel --limit stored-triangles=$line_triangle_cap < "$rendered_list"
total_seconds=$(awk -v s="$start" -v e="$EPOCHREALTIME" 'BEGIN { printf "%.0f", e - s }')

# --- summary -------------------------------------------------------------------------------------
# A refusal's kind: its message without `hsr: error:`, the file name and line number, with quoted
# text and numbers blanked, cut to 100 characters.
kinds_of_refusals() {
    awk -F '\t' '$1 == "refused" {
        kind = $5
        sub(/^hsr: (error: )?/, "", kind)
        if (index(kind, $4) == 1) kind = substr(kind, length($4) + 1)
        sub(/^(:[0-9]+)?: /, "", kind)
        gsub(/\047[^\047]*\047/, "\047...\047", kind)
        print kind
    }' "$1" | sed -E 's/(^|[^A-Za-z0-9_-])-?[0-9]+(\.[0-9]+)?(e-?[0-9]+)?/\1N/g' | cut -c 1-100 | sort | uniq -c |
        sort -rn
}

failed=0
for run in surface altered roberts appel; do
    records=("$scratch/runs/$run"/*)
    [ -e "${records[0]}" ] || continue
    all=$scratch/runs/$run.tsv
    cat "${records[@]}" > "$all"
    tried=$(wc -l < "$all")
    rendered=$(awk -F '\t' '$1 == "rendered"' "$all" | wc -l)
    refused=$(awk -F '\t' '$1 == "refused"' "$all" | wc -l)
    failures=$(awk -F '\t' '$1 == "FAILED"' "$all" | wc -l)
    echo "== $run: $tried files, $rendered rendered, $refused refused with one line, $failures failed"
    kinds_of_refusals "$all" | sed 's/^/   /'
    sort -t $'\t' -k2,2gr "$all" | head -n 1 | awk -F '\t' '{ printf "   slowest: %s s, %s\n", $2, $4 }'
    sort -t $'\t' -k3,3nr "$all" | head -n 1 | awk -F '\t' '{ printf "   largest peak RSS: %d MB, %s\n", $3 / 1024, $4 }'
    awk -F '\t' '$1 == "FAILED" { printf "FAILED %s: %s\n", $4, $5 }' "$all"
    failed=$((failed + failures))
done
echo "== $failed failures, ${total_seconds} s in all"
[ "$failed" -eq 0 ]
