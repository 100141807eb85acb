#!/usr/bin/env bash
# Fetches the two larger test models from Debian 12 packages into this folder (both git-ignored):
#   bunny.obj  - the Stanford bunny (69,666 triangles) from glmark2-data, installed with apt-get
#   monkey.obj - Blender's Suzanne from python-kivy-examples, unpacked from the downloaded .deb
#                without installing it (that package would pull in Python dependencies)
# and installs assimp's test corpus, read in place by the assimp_corpus test:
#   /usr/share/assimp/models - 595 files in about 60 formats, broken ones included, from
#                              assimp-testmodels (74 MB installed, no dependencies)
# Run as root (apt-get install). Safe to run again: it skips what is already there.
#   fetch-models.sh                      all three
#   fetch-models.sh bunny monkey assimp  only those named
set -euo pipefail

wanted=" ${*:-bunny monkey assimp} "
for name in $wanted; do
    case $name in
    bunny|monkey|assimp) ;;
    *) echo "fetch-models.sh: unknown model '$name' (bunny, monkey or assimp)" >&2; exit 2 ;;
    esac
done
wants() { [[ "$wanted" == *" $1 "* ]]; }

models_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export DEBIAN_FRONTEND=noninteractive

apt_updated=0
apt_update_once() {
    if [ "$apt_updated" -eq 0 ]; then
        apt-get update -q
        apt_updated=1
    fi
}

# Installs Debian package $1 unless path $2 (a file or folder it provides) is already there.
install_providing() {
    local package=$1 path=$2
    if [ ! -e "$path" ]; then
        if ! apt-get install -y -q --no-install-recommends "$package"; then
            apt_update_once
            apt-get install -y -q --no-install-recommends "$package"
        fi
    fi
    if [ ! -e "$path" ]; then
        echo "fetch-models.sh: $package is installed but $path is missing" >&2
        exit 1
    fi
}

# --- bunny.obj ---------------------------------------------------------------------------------
if wants bunny; then
    bunny_source=/usr/share/glmark2/models/bunny.obj
    install_providing glmark2-data "$bunny_source"
    if ! cmp -s "$bunny_source" "$models_dir/bunny.obj"; then
        cp "$bunny_source" "$models_dir/bunny.obj"
    fi
    echo "bunny.obj:  $models_dir/bunny.obj"
fi

# --- monkey.obj --------------------------------------------------------------------------------
if wants monkey; then
    monkey_member=usr/share/kivy-examples/3Drendering/monkey.obj
    if [ ! -s "$models_dir/monkey.obj" ]; then
        work_dir="$(mktemp -d)"
        trap 'rm -rf "$work_dir"' EXIT
        # apt-get download writes into the current directory as the unprivileged _apt user when it
        # can; let that user write there (otherwise apt warns and downloads as root).
        if id _apt > /dev/null 2>&1; then chown _apt "$work_dir"; fi
        if ! (cd "$work_dir" && apt-get download -q python-kivy-examples); then
            apt_update_once
            (cd "$work_dir" && apt-get download -q python-kivy-examples)
        fi
        deb_file="$(find "$work_dir" -maxdepth 1 -name 'python-kivy-examples_*.deb' | head -n 1)"
        if [ -z "$deb_file" ]; then
            echo "fetch-models.sh: apt-get download python-kivy-examples produced no .deb" >&2
            exit 1
        fi
        dpkg -x "$deb_file" "$work_dir/unpacked"
        if [ ! -f "$work_dir/unpacked/$monkey_member" ]; then
            echo "fetch-models.sh: $monkey_member is not in $(basename "$deb_file")" >&2
            exit 1
        fi
        cp "$work_dir/unpacked/$monkey_member" "$models_dir/monkey.obj.partial"
        mv "$models_dir/monkey.obj.partial" "$models_dir/monkey.obj"
    fi
    echo "monkey.obj: $models_dir/monkey.obj"
fi

# --- assimp-testmodels -------------------------------------------------------------------------
if wants assimp; then
    assimp_corpus=/usr/share/assimp/models
    install_providing assimp-testmodels "$assimp_corpus"
    echo "assimp corpus: $assimp_corpus"
fi
