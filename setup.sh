#!/usr/bin/env bash
# The README's two commands:
#   bash setup.sh render   install what is missing, build, render the default scene to bunny.png
#   bash setup.sh test     install what is missing, build, run the whole test suite (CI runs this)
# Needs root (or sudo) on Debian 12 for the package step; everything else stays in this folder.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

packages=(g++ cmake make pkg-config libboost-dev libboost-program-options-dev libboost-filesystem-dev
          libopenmesh-dev libglm-dev libfmt-dev catch2 libpng-dev libcairo2-dev libmuparser-dev valgrind time)

install_missing() {
    local missing=()
    for p in "${packages[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    echo "setup: installing ${missing[*]}"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

build() {
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
    cmake --build build -j"$(nproc)"
}

case "${1:-}" in
render)
    install_missing
    bash models/fetch-models.sh
    build
    build/hsr render models/bunny.obj --algorithm zbuffer --lighting blinn-phong -o bunny.png
    ;;
test)
    install_missing
    bash models/fetch-models.sh
    build
    ctest --test-dir build --output-on-failure -j"$(nproc)"
    ;;
*)
    echo "usage: bash setup.sh render|test" >&2
    exit 2
    ;;
esac
