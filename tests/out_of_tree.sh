#!/usr/bin/env bash
# Installs hsr from a build tree to a temporary prefix, builds the three plugins of
# docs/example-plugin against it with find_package(hsr), loads them through --plugin-path and checks
# their pictures against independent answers:
#   simple-zbuffer  the same PNG and depth PNG, byte for byte, as the bundled zbuffer (cube, monkey,
#                   and instanced cubes)
#   normals         the same PNG as facecolor on a cube whose faces are coloured by hand with
#                   (n + 1) / 2 of their known normals (world space, and camera space seen from +x)
#   wireframe       all 12 edges of the cube, none hidden, on the lines that the bundled roberts
#                   draws (visible and dashed hidden together)
# and builds normals once more against the build tree's package (-Dhsr_DIR=<build>/sdk).
#   out_of_tree.sh <source dir> <build dir>
set -euo pipefail
src=$1
build=$2
models=$src/models
work=$(mktemp -d "$build/out-of-tree.XXXXXX")
trap 'rm -rf "$work"' EXIT

fail() {
    echo "out_of_tree: $*" >&2
    exit 1
}

if [ ! -f "$models/monkey.obj" ]; then
    fail "models not fetched: run models/fetch-models.sh"
fi

# --- install, build, list -----------------------------------------------------------------------

cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
for header in abi.h sdk.hpp raster.hpp triangle_setup.hpp bounds.hpp zpyramid.hpp shading.hpp parallel.hpp; do
    test -f "$work/prefix/include/hsr/$header" || fail "the install has no include/hsr/$header"
done
cmake -S "$src/docs/example-plugin" -B "$work/example" -DCMAKE_PREFIX_PATH="$work/prefix" \
      -DCMAKE_BUILD_TYPE=Release > "$work/configure.log"
cmake --build "$work/example" > "$work/build.log" || { cat "$work/build.log" >&2; fail "the examples do not build"; }

hsr=$work/prefix/bin/hsr
plugins=$work/example
"$hsr" plugins --plugin-path "$plugins" > "$work/plugins.txt"
for listed in "lighting +normals " "hidden-surface +simple-zbuffer " "hidden-line +wireframe "; do
    grep -Eq "^$listed" "$work/plugins.txt" || fail "hsr plugins does not list '$listed'"
done

render() {  # render <name> <hsr render arguments...>: writes $work/<name>.png (or what -o names)
    local name=$1
    shift
    "$hsr" render "$@" --plugin-path "$plugins" --width 256 --height 192 > "$work/$name.log" 2>&1 ||
        { cat "$work/$name.log" >&2; fail "hsr render $* failed"; }
}

same() {  # same <file> <file> <what>
    cmp -s "$1" "$2" || fail "$3: $(basename "$1") and $(basename "$2") differ"
}

# --- simple-zbuffer: byte for byte the bundled zbuffer --------------------------------------------

for model in cube monkey; do
    for algorithm in zbuffer simple-zbuffer; do
        render "$model-$algorithm" "$models/$model.obj" --yaw 30 --pitch 20 --algorithm "$algorithm" \
               -o "$work/$model-$algorithm.png" --depth-out "$work/$model-$algorithm-depth.png"
    done
    same "$work/$model-zbuffer.png" "$work/$model-simple-zbuffer.png" "simple-zbuffer on $model.obj"
    same "$work/$model-zbuffer-depth.png" "$work/$model-simple-zbuffer-depth.png" "simple-zbuffer's depth on $model.obj"
done
# Instances (each copy of the cube is one placement), and the per-pixel depth-test counts.
for algorithm in zbuffer simple-zbuffer; do
    render "cubes-$algorithm" "$models/cube.obj" --repeat 3x2x2 --repeat-jitter 30 --yaw 20 --pitch 10 \
           --algorithm "$algorithm" -o "$work/cubes-$algorithm.png" --depth-tests-out "$work/cubes-$algorithm-tests.png"
done
same "$work/cubes-zbuffer.png" "$work/cubes-simple-zbuffer.png" "simple-zbuffer on instanced cubes"
same "$work/cubes-zbuffer-tests.png" "$work/cubes-simple-zbuffer-tests.png" "simple-zbuffer's depth-test counts"
# Without the depth test the back of the monkey shows through.
render monkey-overdraw "$models/monkey.obj" --yaw 30 --pitch 20 --algorithm simple-zbuffer:depth-test=false \
       -o "$work/monkey-overdraw.png"
! cmp -s "$work/monkey-zbuffer.png" "$work/monkey-overdraw.png" || fail "simple-zbuffer:depth-test=false hides like a z-buffer"

# --- normals: the colour of each cube face is (n + 1) / 2 of its normal n -------------------------

cube_scene() {  # cube_scene <file> <colours of the faces +x -x +y -y +z -z, each "r g b">
    local file=$1
    shift
    {
        printf 'polygon\n  color %s\n  vertex 1 -1 -1\n  vertex 1 1 -1\n  vertex 1 1 1\n  vertex 1 -1 1\n' "$1"
        printf 'polygon\n  color %s\n  vertex -1 -1 -1\n  vertex -1 -1 1\n  vertex -1 1 1\n  vertex -1 1 -1\n' "$2"
        printf 'polygon\n  color %s\n  vertex -1 1 -1\n  vertex -1 1 1\n  vertex 1 1 1\n  vertex 1 1 -1\n' "$3"
        printf 'polygon\n  color %s\n  vertex -1 -1 -1\n  vertex 1 -1 -1\n  vertex 1 -1 1\n  vertex -1 -1 1\n' "$4"
        printf 'polygon\n  color %s\n  vertex -1 -1 1\n  vertex 1 -1 1\n  vertex 1 1 1\n  vertex -1 1 1\n' "$5"
        printf 'polygon\n  color %s\n  vertex -1 -1 -1\n  vertex -1 1 -1\n  vertex 1 1 -1\n  vertex 1 -1 -1\n' "$6"
    } > "$file"
}
# World space: +x is (1, 0, 0), coloured (1, 0.5, 0.5), and so on.
cube_scene "$work/world.scene" "1 0.5 0.5" "0 0.5 0.5" "0.5 1 0.5" "0.5 0 0.5" "0.5 0.5 1" "0.5 0.5 0"
render world-normals "$work/world.scene" --yaw 30 --pitch 20 --lighting normals -o "$work/world-normals.png"
render world-expected "$work/world.scene" --yaw 30 --pitch 20 --lighting facecolor -o "$work/world-expected.png"
same "$work/world-expected.png" "$work/world-normals.png" "normals on a cube (world space)"
# Camera space, the eye on +x (yaw 90): x right = world -z, y up = world y, z toward the eye = world x.
cube_scene "$work/camera.scene" "0.5 0.5 1" "0.5 0.5 0" "0.5 1 0.5" "0.5 0 0.5" "0 0.5 0.5" "1 0.5 0.5"
render camera-normals "$work/camera.scene" --yaw 90 --lighting normals:view-space=true -o "$work/camera-normals.png"
render camera-expected "$work/camera.scene" --yaw 90 --lighting facecolor -o "$work/camera-expected.png"
same "$work/camera-expected.png" "$work/camera-normals.png" "normals:view-space=true on a cube seen from +x"

# --- wireframe: every edge of the cube, where roberts draws it --------------------------------------

# The segments of an SVG that hsr wrote (cairo paths of "M x0 y0 L x1 y1" pieces), one per line.
segments() {
    grep -o ' d="[^"]*"' "$1" | sed 's/^ d="//; s/"$//; s/M /\nM /g' | awk '$1 == "M" && $4 == "L" { print $2, $3, $5, $6 }'
}
# Pairs the segments of two lists, either way round, end points within 0.01 pixel; prints those of
# either list left without a partner.
unpaired() {
    awk 'function near(a, b) { return a - b < 0.01 && b - a < 0.01 }
         NR == FNR { x0[NR] = $1; y0[NR] = $2; x1[NR] = $3; y1[NR] = $4; n = NR; next }
         {
             for (k = 1; k <= n; ++k) {
                 if (taken[k]) continue
                 if ((near($1, x0[k]) && near($2, y0[k]) && near($3, x1[k]) && near($4, y1[k])) ||
                     (near($1, x1[k]) && near($2, y1[k]) && near($3, x0[k]) && near($4, y0[k]))) {
                     taken[k] = 1
                     next
                 }
             }
             print "only in " FILENAME ": " $0
         }
         END { for (k = 1; k <= n; ++k) if (!taken[k]) print "only in " ARGV[1] ": " x0[k], y0[k], x1[k], y1[k] }' "$1" "$2"
}
render cube-wireframe "$models/cube.obj" --yaw 30 --pitch 20 --edges all --algorithm wireframe \
       -o "$work/cube-wireframe.svg" --trace "$work/cube-wireframe.jsonl" --stats
render cube-roberts "$models/cube.obj" --yaw 30 --pitch 20 --edges all --hidden dashed --algorithm roberts \
       -o "$work/cube-roberts.svg"
grep -q ", 12 visible segments, 12 edges," "$work/cube-wireframe.log" ||
    fail "wireframe does not draw the cube's 12 edges, all visible: $(grep '^wrote.*svg' "$work/cube-wireframe.log")"
[ "$(grep -c '"type":"edge-begin"' "$work/cube-wireframe.jsonl")" -eq 12 ] || fail "wireframe's trace has no 12 edge-begin steps"
segments "$work/cube-wireframe.svg" > "$work/cube-wireframe.segments"
segments "$work/cube-roberts.svg" > "$work/cube-roberts.segments"
[ "$(wc -l < "$work/cube-roberts.segments")" -eq 12 ] || fail "roberts drew the cube's edges in other than 12 pieces"
unpaired "$work/cube-roberts.segments" "$work/cube-wireframe.segments" > "$work/unpaired.txt"
[ ! -s "$work/unpaired.txt" ] ||
    { cat "$work/unpaired.txt" >&2; fail "wireframe's lines are not the cube's edges that roberts draws"; }

# --- the build tree's package: -Dhsr_DIR=<build>/sdk, no install --------------------------------

cmake -S "$src/docs/example-plugin" -B "$work/from-build-tree" -Dhsr_DIR="$build/sdk" \
      -DCMAKE_BUILD_TYPE=Release > "$work/configure-build-tree.log" ||
    { cat "$work/configure-build-tree.log" >&2; fail "find_package(hsr) with hsr_DIR=<build>/sdk fails"; }
cmake --build "$work/from-build-tree" --target plugin_normals > "$work/build-build-tree.log" ||
    { cat "$work/build-build-tree.log" >&2; fail "the normals example does not build against the build tree"; }
"$build/hsr" plugins --plugin-path "$work/from-build-tree" > "$work/plugins-build-tree.txt"
grep -Eq "^lighting +normals " "$work/plugins-build-tree.txt" || fail "the build tree's hsr does not list normals built against it"

echo "out_of_tree: the three example plugins built, loaded and drew what they should; normals built against the build tree too"
