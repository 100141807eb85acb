#!/usr/bin/env bash
# Installs the SDK from a build tree to a temporary prefix, builds docs/example-plugin against it
# with find_package(hsr), and renders with the result through --plugin-path.
#   out_of_tree.sh <source dir> <build dir>
set -euo pipefail
src=$1
build=$2
work=$(mktemp -d "$build/out-of-tree.XXXXXX")
trap 'rm -rf "$work"' EXIT

cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
test -f "$work/prefix/include/hsr/abi.h"
test -f "$work/prefix/include/hsr/sdk.hpp"
cmake -S "$src/docs/example-plugin" -B "$work/example" -DCMAKE_PREFIX_PATH="$work/prefix" \
      -DCMAKE_BUILD_TYPE=Release > "$work/configure.log"
cmake --build "$work/example" > "$work/build.log"
test -f "$work/example/hsr-normals.so"

# The installed host finds the installed plugins by itself and the new one through --plugin-path.
"$work/prefix/bin/hsr" plugins --plugin-path "$work/example" | grep -E "^lighting +normals "
"$work/prefix/bin/hsr" render "$src/models/cube.obj" --lighting normals:view-space=true \
    --plugin-path "$work/example" --width 64 --height 64 -o "$work/cube-normals.png"
test -s "$work/cube-normals.png"
echo "out-of-tree plugin built, loaded and rendered"
