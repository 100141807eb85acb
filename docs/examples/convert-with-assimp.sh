#!/usr/bin/env bash
# A model in a format hsr does not read (3DS, DAE, FBX, and the rest assimp knows) rendered
# through a conversion to glTF with Debian's assimp-utils. docs/formats.md explains it; the test
# `assimp_recipe` (tests/CMakeLists.txt) runs it on a 3DS, a DAE and an FBX file.
#   convert-with-assimp.sh HSR MODEL PICTURE.png
set -euo pipefail
hsr=$1 model=$2 picture=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# assimp reads the model and writes it as binary glTF: meshes, node transforms, materials' colours.
assimp export "$model" "$work/model.glb" > "$work/assimp.log" || { cat "$work/assimp.log" >&2; exit 1; }

"$hsr" render "$work/model.glb" --yaw 30 --pitch 20 --stats -o "$picture"
