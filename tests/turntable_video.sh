#!/usr/bin/env bash
# Runs docs/examples/turntable-video.sh and checks what came out with ffprobe and ffmpeg: a GIF of
# the 36 frames and an MP4 of 72 (each frame twice), 320x320, whose frames are the PNGs in order
# (frame k of the video is nearer, by PSNR, to PNG k than to PNG k+9). Exit 77 (skipped) without
# ffmpeg.
#   turntable_video.sh SOURCE_DIR HSR MODEL OUT_DIR
set -euo pipefail
src=$1 hsr=$2 model=$3 out=$4
for tool in ffmpeg ffprobe; do
    command -v "$tool" > /dev/null || { echo "skipped: $tool is not installed (Debian: apt-get install ffmpeg)"; exit 77; }
done
rm -rf "$out"
bash "$src/docs/examples/turntable-video.sh" "$hsr" "$model" "$out" 2> "$out.log" || { cat "$out.log"; exit 1; }

fail() { echo "FAIL: $*"; exit 1; }
probe() {  # codec,width,height,frames
    ffprobe -v error -count_frames -select_streams v:0 \
        -show_entries stream=codec_name,width,height,nb_read_frames -of csv=p=0 "$1"
}
[ "$(probe "$out/turn.gif")" = "gif,320,320,36" ] || fail "turn.gif: $(probe "$out/turn.gif")"
[ "$(probe "$out/turn.mp4")" = "h264,320,320,72" ] || fail "turn.mp4: $(probe "$out/turn.mp4")"

# The PSNR in dB of frame `index` of a video against a PNG.
psnr() {
    ffmpeg -v info -i "$1" -i "$3" -lavfi "[0:v]select=eq(n\,$2),format=rgb24[a];[1:v]format=rgb24[b];[a][b]psnr" \
        -frames:v 1 -f null - 2>&1 | sed -n 's/.* average:\([0-9.inf]*\).*/\1/p' | head -1
}
check_frame() {  # video, video frame, PNG frame it shows
    local same other
    same=$(psnr "$1" "$2" "$(printf "$out/frames/turn-%03d.png" "$3")")
    other=$(psnr "$1" "$2" "$(printf "$out/frames/turn-%03d.png" $(( ($3 + 9) % 36 )))")
    echo "$(basename "$1") frame $2: ${same} dB against turn-$(printf %03d "$3").png, ${other} dB against the frame 90 degrees on"
    awk -v a="$same" -v b="$other" 'BEGIN { exit !(a == "inf" || (a + 0 > 25 && a + 0 > b + 5)) }' ||
        fail "$(basename "$1") frame $2 is not turn-$(printf %03d "$3").png"
}
check_frame "$out/turn.gif" 0 0
check_frame "$out/turn.gif" 20 20
check_frame "$out/turn.mp4" 0 0
check_frame "$out/turn.mp4" 41 20
echo "turntable video: ok"
