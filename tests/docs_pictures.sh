#!/usr/bin/env bash
# Checks that the docs' commands make the docs' pictures: runs docs/images/make.sh --quick (every
# picture block of README.md and docs/ but those marked slow, which it names) into a scratch folder
# and compares each picture made with the committed one in docs/images/, PNG files by their pixels
# and other files byte for byte (tests/tools/same_pictures.py). Rendering is deterministic (one
# answer on any number of threads), so the comparison is exact.
#   docs_pictures.sh SOURCE_DIR HSR_BINARY WORK_DIR [PYTHON]
set -euo pipefail
src=$1
hsr=$2
work=$3
python=${4:-python3}
for needed in "$src/models/bunny.obj" "$src/models/monkey.obj" /usr/share/assimp/models/glTF2; do
    [ -e "$needed" ] || { echo "models not fetched: run models/fetch-models.sh ($needed)"; exit 0; }
done
rm -rf "$work"
mkdir -p "$work/made" "$work/committed"
bash "$src/docs/images/make.sh" "$hsr" --quick --out "$work/made"
for made in "$work/made"/*; do
    cp "$src/docs/images/$(basename "$made")" "$work/committed/"
done
if ! "$python" "$src/tests/tools/same_pictures.py" "$work/committed" "$work/made"; then
    echo "docs_pictures: the pictures above are not what the commands beside them in the docs make" >&2
    echo "docs_pictures: docs/images/make.sh makes them again" >&2
    exit 1
fi
