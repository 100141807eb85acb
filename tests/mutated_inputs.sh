#!/usr/bin/env bash
# Mutated model and scene files (tests/tools/mutate_inputs.cpp: numbers replaced by extremes, lines
# repeated, bytes flipped, inserted, cut, duplicated, files truncated), each rendered by
# model_corpus.sh: it renders, or is refused with one line, within 10 s and 1 GB; those that render
# are drawn again by roberts and appel. The seeds are the small models and scenes of models/ (and
# monkey.obj once fetched) and the files of tests/data/bad/; the same seed number gives the same
# mutants, so a failure can be made again.
#
#   mutated_inputs.sh <hsr binary> <mutate_inputs binary> <source dir> <scratch dir> <count> <seed number>
set -euo pipefail

if [ $# -ne 6 ]; then
    echo "usage: mutated_inputs.sh <hsr binary> <mutate_inputs binary> <source dir> <scratch dir> <count> <seed number>" >&2
    exit 2
fi
hsr=$1 mutate=$2 source=$3 scratch=$4 count=$5 seed=$6

seeds=("$source"/models/{cube.obj,octahedron.ply,pyramid.stl,tetrahedron.off,boxes.scene,three-polygons.scene})
[ -s "$source/models/monkey.obj" ] && seeds+=("$source/models/monkey.obj")
seeds+=("$source"/tests/data/bad/*)

rm -rf "$scratch"
"$mutate" "$scratch/inputs" "$count" "$seed" "${seeds[@]}"
bash "$source/tests/model_corpus.sh" --no-altered "$hsr" "$scratch/inputs" "$scratch/runs"
