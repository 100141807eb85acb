#!/usr/bin/env bash
# A turntable of the bunny as an animated GIF and an MP4 video: hsr renders the 36 frames, ffmpeg
# (Debian's ffmpeg package) joins them. docs/many-frames.md explains it; the test
# `turntable_video` (tests/CMakeLists.txt) runs it.
#   turntable-video.sh HSR MODEL OUT_DIR
set -euo pipefail
hsr=$1 model=$2 out=$3
mkdir -p "$out/frames"

# 36 frames, 10 degrees apart: frames/turn-000.png ... frames/turn-035.png.
"$hsr" render "$model" --views 36 --pitch 15 --width 320 --height 320 -o "$out/frames/turn-%03d.png"

# A GIF at 12 frames a second, with a palette made for these frames (ffmpeg's default palette
# bands the shading).
ffmpeg -loglevel error -y -framerate 12 -i "$out/frames/turn-%03d.png" \
    -vf "split[a][b];[a]palettegen=max_colors=128[p];[b][p]paletteuse" -loop 0 "$out/turn.gif"

# An MP4 (H.264, yuv420p so that every player shows it), at 24 frames a second: each frame twice.
ffmpeg -loglevel error -y -framerate 12 -i "$out/frames/turn-%03d.png" \
    -c:v libx264 -pix_fmt yuv420p -r 24 -crf 20 -movflags +faststart "$out/turn.mp4"
