#!/usr/bin/env bash
# The README's commands:
#   bash setup.sh render      install what the build needs, fetch the bunny, build hsr and its
#                             plugins (no tests), render the bunny to bunny.png
#   bash setup.sh test        install what is missing, build, run the whole test suite (CI runs this):
#                             first a Release build in build/, then the same suite built with clang
#                             under AddressSanitizer + UndefinedBehaviorSanitizer in build-sanitize/
#   bash setup.sh test quick  the Release build and every test but those labelled `slow`; no
#                             sanitizer stage (the loop while changing code)
# Needs root (or sudo) on Debian 12 for the package step; everything else stays in this folder.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

# What building hsr and its plugins needs.
build_packages=(g++ cmake make pkg-config libboost-dev libboost-program-options-dev libboost-filesystem-dev
                libopenmesh-dev libglm-dev libfmt-dev libpng-dev libisal-dev libcairo2-dev libmuparser-dev
                libcpp-httplib-dev nlohmann-json3-dev libcmark-gfm-dev libcmark-gfm-extensions-dev libembree-dev libtbb-dev libhwy-dev
                libtinygltf-dev libopenexr-dev)
# What the tests need besides: Catch2; valgrind, GNU time, clang and its sanitizer runtime; the
# browser test's chromium; NumPy, the Python package's headers and pybind11, pytest and Dask; assimp
# and ffmpeg for the docs' conversion and video examples.
test_packages=(catch2 valgrind time clang libclang-rt-14-dev chromium python3-numpy assimp-utils ffmpeg
               python3-dev pybind11-dev python3-pytest python3-distributed)

install_missing() {  # install_missing <package>...
    local missing=()
    for p in "$@"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    echo "setup: installing ${missing[*]}"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

# playwright-core for the browser test (tests/browser), from its lockfile; the test itself drives
# Debian's chromium. Node.js and npm come with the machine.
install_browser_test() {
    (cd tests/browser && npm ci --prefer-offline --no-audit --no-fund --loglevel=error)
}

build() {
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=ON -DHSR_BUILD_PYTHON=ON
    cmake --build build -j"$(nproc)"
}

# hsr and the bundled plugins only, in the same build/ that `setup.sh test` completes later.
build_for_rendering() {
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DHSR_BUILD_PYTHON=OFF
    cmake --build build -j"$(nproc)" --target hsr hsr_plugins
}

# The sanitizer stage: everything (host, framework, plugins, tests) built by clang with
# -fsanitize=address,undefined (HSR_SANITIZE, CMakeLists.txt) at -O1, and the whole suite run with
# leak checking; docs/robustness.md#sanitizer-build says what is left out and why. The same build
# has the libFuzzer targets (HSR_FUZZ, fuzz/), whose tests fuzz each reader for 30 s.
build_sanitized() {
    CC=clang CXX=clang++ cmake -S . -B build-sanitize -DHSR_SANITIZE=ON -DHSR_FUZZ=ON -DCMAKE_BUILD_TYPE=Debug \
        -DCMAKE_C_FLAGS_DEBUG="-O1 -gline-tables-only" -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only"
    cmake --build build-sanitize -j"$(nproc)"
}

# A sanitizer report exits with 86, so that a test expecting hsr to fail with 1 or 2 notices it too.
# The tests labelled `slow` (about 1,250 s of test time under the sanitizers) are left to
# `ctest --test-dir build-sanitize -L slow`, with the same environment.
test_sanitized() {
    ASAN_OPTIONS=detect_leaks=1:exitcode=86 \
    LSAN_OPTIONS=suppressions="$PWD/tests/sanitizers/lsan.supp" \
    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
        ctest --test-dir build-sanitize --output-on-failure -j"$(nproc)" --label-exclude slow
}

case "${1:-} ${2:-}" in
"render ")
    install_missing "${build_packages[@]}"
    bash models/fetch-models.sh bunny
    build_for_rendering
    build/hsr render models/bunny.obj --algorithm zbuffer --lighting blinn-phong -o bunny.png
    ;;
"test "|"test quick")
    install_missing "${build_packages[@]}" "${test_packages[@]}"
    install_browser_test
    export HSR_BROWSER_TEST_REQUIRED=1  # a skipped browser test fails the run
    bash models/fetch-models.sh
    build
    if [ "${2:-}" = quick ]; then
        ctest --test-dir build --output-on-failure -j"$(nproc)" --label-exclude slow
    else
        ctest --test-dir build --output-on-failure -j"$(nproc)"
        build_sanitized
        test_sanitized
    fi
    ;;
*)
    echo "usage: bash setup.sh render | test | test quick" >&2
    exit 2
    ;;
esac
