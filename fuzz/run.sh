#!/usr/bin/env bash
# Fuzzes one target for a bounded time, as the ctest test fuzz_<target> does (docs/fuzzing.md):
#   run.sh FUZZER TARGET SECONDS FUZZ_SOURCE_DIR BUILD_DIR [SEED]
# SEED (libFuzzer's -seed) makes a run repeatable: the same code and seed try the same inputs in the
# same order, as far as the time allows; 0 or none lets libFuzzer pick a new one.
# The seed corpus and the kept regressions are copied into BUILD_DIR/fuzz-corpus/TARGET, which
# libFuzzer grows (the source tree is never written). Any crash, leak, timeout (> 10 s for one
# input) or out-of-memory (> 1 GB) fails the run; the input is then in
# BUILD_DIR/fuzz-artifacts/TARGET/, and this script prints it and how to keep it as a regression.
set -euo pipefail
if [ $# -ne 5 ] && [ $# -ne 6 ]; then
  echo "usage: $0 FUZZER TARGET SECONDS FUZZ_SOURCE_DIR BUILD_DIR [SEED]" >&2
  exit 2
fi
fuzzer=$1 target=$2 seconds=$3 source=$4 build=$5 seed=${6:-0}

corpus=$build/fuzz-corpus/$target
artifacts=$build/fuzz-artifacts/$target
mkdir -p "$corpus" "$artifacts"
cp -r "$source/corpus/$target/." "$source/regressions/$target/." "$corpus/"
marker=$(mktemp)
trap 'rm -f "$marker"' EXIT

status=0
"$fuzzer" -seed="$seed" -max_total_time="$seconds" -rss_limit_mb=1024 -timeout=10 -print_final_stats=1 \
  -artifact_prefix="$artifacts/" "$corpus" || status=$?
if [ "$status" -eq 0 ]; then exit 0; fi

echo
echo "fuzz_$target: libFuzzer stopped with status $status"
found=0
while IFS= read -r -d '' artifact; do
  found=1
  echo "input: $artifact ($(stat -c %s "$artifact") bytes)"
  xxd "$artifact" | head -n 16
  echo "keep it as a regression (from the source folder):"
  echo "  cp '$artifact' fuzz/regressions/$target/"
done < <(find "$artifacts" -type f -newer "$marker" -print0)
if [ "$found" -eq 0 ]; then echo "no input was written to $artifacts"; fi
exit 1
