#!/usr/bin/env bash
# Runs docs/examples/convert-with-assimp.sh on a 3DS, a DAE and an FBX file of assimp's test corpus:
# each gives a picture in which something is drawn (over 1,000 pixels shaded, from --stats). Exit 77
# (skipped) without assimp or the corpus.
#   assimp_recipe.sh SOURCE_DIR HSR CORPUS_DIR OUT_DIR
set -euo pipefail
src=$1 hsr=$2 corpus=$3 out=$4
command -v assimp > /dev/null || { echo "skipped: assimp is not installed (Debian: apt-get install assimp-utils)"; exit 77; }
[ -d "$corpus" ] || { echo "skipped: no assimp test corpus at $corpus (Debian: assimp-testmodels)"; exit 77; }
rm -rf "$out"
mkdir -p "$out"
status=0
for model in 3DS/cubes_with_alpha.3DS Collada/duck.dae FBX/cubes_with_names.fbx; do
    picture="$out/$(basename "$model").png"
    if ! bash "$src/docs/examples/convert-with-assimp.sh" "$hsr" "$corpus/$model" "$picture" 2> "$out/err.txt"; then
        echo "FAIL: $model: $(cat "$out/err.txt")"
        status=1
        continue
    fi
    covered=$(sed -n 's/^ *fragments-shaded *\([0-9]*\)$/\1/p' "$out/err.txt")
    echo "$model: rendered to $(basename "$picture"), ${covered:-no} pixels shaded"
    [ "${covered:-0}" -gt 1000 ] || { echo "FAIL: $model: nothing drawn"; cat "$out/err.txt"; status=1; }
done
exit $status
