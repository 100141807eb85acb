#!/usr/bin/env bash
# Renders a fixed set of pictures with one build of hsr: every hidden-surface plugin with every
# lighting model on the bunny, the monkey, boxes.scene and deep-monkeys.scene (PNG and depth PNG),
# their --stats counters and heat maps, the hidden-line plugins' SVG, PNG and traces, and two deep
# instanced scenes. A change that must not alter any picture (a refactor, a speed-up) is checked by
# running it with the build before and after and comparing the two folders:
#   tests/picture_set.sh old-build/hsr models /tmp/before
#   tests/picture_set.sh build/hsr models /tmp/after
#   diff -r /tmp/before /tmp/after && echo identical
# Timings are left out of the counters' files, so two runs of one build compare equal.
set -euo pipefail
if [ $# -ne 3 ]; then
    echo "usage: tests/picture_set.sh HSR_BINARY MODELS_DIR OUT_DIR" >&2
    exit 2
fi
hsr=$1
models=$2
out=$3
mkdir -p "$out"
rm -f "$out/failures.txt"

for model in bunny.obj monkey.obj deep-monkeys.scene boxes.scene; do
    name=${model%.*}
    for algorithm in zbuffer scanline-zbuffer hierarchical-zbuffer octree-zbuffer; do
        for lighting in blinn-phong lambert phong:interpolation=gouraud facecolor; do
            shown=${lighting%%:*}
            "$hsr" render "$models/$model" -a "$algorithm" -l "$lighting" --width 256 --height 256 \
                --yaw 30 --pitch -15 -o "$out/$name-$algorithm-$shown.png" \
                --depth-out "$out/$name-$algorithm-$shown-depth.png" 2> /dev/null
        done
        "$hsr" render "$models/$model" -a "$algorithm" --width 200 --height 160 --stats \
            --overdraw-out "$out/$name-$algorithm-od.png" --depth-tests-out "$out/$name-$algorithm-dt.png" \
            -o "$out/$name-$algorithm-s.png" 2>&1 | grep -v -i "time\|-us\b\| ms\|wrote" \
            > "$out/$name-$algorithm-stats.txt" || true
    done
done

# roberts refuses the non-convex bunny and monkey: the refusals are part of the set.
for model in bunny.obj monkey.obj boxes.scene; do
    name=${model%.*}
    for algorithm in appel roberts; do
        "$hsr" render "$models/$model" -a "$algorithm" --hidden dashed --edges all --yaw 30 --pitch 10 \
            --width 300 --height 300 -o "$out/$name-$algorithm.svg" 2> /dev/null ||
            echo "fail $model $algorithm" >> "$out/failures.txt"
        "$hsr" render "$models/$model" -a "$algorithm" --yaw 30 --pitch 10 --width 300 --height 300 \
            -o "$out/$name-$algorithm.png" --trace "$out/$name-$algorithm.jsonl" 2> /dev/null ||
            echo "fail $model $algorithm png" >> "$out/failures.txt"
    done
done
for format in png svg; do
    "$hsr" render --surface "sin(x)*cos(y)" --range -3:3,-3:3,48x48 --pitch 30 --algorithm floating-horizon \
        --edges all -o "$out/fh.$format" > /dev/null
done
"$hsr" render "$models/bunny.obj" --repeat 4x4x6 -a octree-zbuffer -o "$out/bunny-repeat-oct.png" \
    --width 300 --height 300 > /dev/null
"$hsr" render "$models/bunny.obj" --repeat 4x4x6 -a scanline-zbuffer -o "$out/bunny-repeat-scan.png" \
    --width 300 --height 300 > /dev/null
