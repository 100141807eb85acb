#!/usr/bin/env bash
# Installs hsr from a build tree as the README shows, `cmake --install build --prefix ~/.local`, with
# HOME a temporary folder, and runs the installed hsr from PATH in an unrelated folder: it must find
# every bundled plugin in <prefix>/lib/hsr/plugins and nowhere else, render there, and have the SDK,
# its CMake package, the docs and the models beside it. When the Python package is built, Debian's
# python3 must import the installed one from the user site, without PYTHONPATH.
#   install_prefix.sh <source dir> <build dir> <python>
set -euo pipefail
src=$1
build=$2
python=$3
work=$(mktemp -d "${TMPDIR:-/tmp}/hsr-install.XXXXXX")
trap 'rm -rf "$work"' EXIT

fail() {
    echo "install_prefix: $*" >&2
    exit 1
}

export HOME=$work/home
unset PYTHONUSERBASE PYTHONPATH HSR_PLUGIN_PATH
prefix=$HOME/.local
cmake --install "$build" --prefix "$prefix" > "$work/install.log" || { cat "$work/install.log" >&2; fail "cmake --install failed"; }
for file in bin/hsr include/hsr/abi.h include/hsr/sdk.hpp lib/cmake/hsr/hsrConfig.cmake lib/cmake/hsr/hsrTargets.cmake \
            share/doc/hsr/README.md share/doc/hsr/docs/writing-a-plugin.md share/doc/hsr/docs/images/bunny-blinn-phong.png \
            share/hsr/models/boxes.scene share/hsr/models/cube.obj; do
    [ -e "$prefix/$file" ] || fail "the install has no $file"
done
[ ! -e "$prefix/share/hsr/models/fetch-models.sh" ] || fail "the install has models/fetch-models.sh"

mkdir "$work/elsewhere"
cd "$work/elsewhere"
export PATH="$prefix/bin:$PATH"
[ "$(command -v hsr)" = "$prefix/bin/hsr" ] || fail "hsr on PATH is $(command -v hsr), not the installed one"

hsr plugins > plugins.txt 2>&1 || { cat plugins.txt >&2; fail "the installed hsr plugins failed"; }
# The searched folders are listed first, each on a line of its own, indented.
searched=$(awk '/^searched:/ { on = 1; next } on && /^  / { print $1; next } { on = 0 }' plugins.txt)
[ -n "$searched" ] || fail "hsr plugins names no searched folder"
while read -r dir; do
    case $dir in
    "$prefix"/*) ;;
    *) [ ! -d "$dir" ] || fail "the installed hsr searches $dir, outside its prefix" ;;
    esac
done <<< "$searched"
bundled=$(find "$build/plugins" -maxdepth 1 -name 'hsr-*.so' | wc -l)
installed=$(find "$prefix/lib/hsr/plugins" -maxdepth 1 -name 'hsr-*.so' | wc -l)
[ "$bundled" -gt 0 ] && [ "$installed" -eq "$bundled" ] || fail "$installed plugins installed of the $bundled built"
listed=$(grep -cE '^(hidden-surface|hidden-line|lighting) ' plugins.txt)
[ "$listed" -eq "$bundled" ] || fail "the installed hsr lists $listed plugins, $bundled are bundled"

hsr render "$prefix/share/hsr/models/cube.obj" --algorithm zbuffer --lighting blinn-phong --width 64 --height 48 \
    -o cube.png > render.log 2>&1 || { cat render.log >&2; fail "the installed hsr does not render"; }
[ -s cube.png ] || fail "the installed hsr wrote no cube.png in the folder it ran in"
hsr render "$prefix/share/hsr/models/boxes.scene" --algorithm roberts -o boxes.svg > lines.log 2>&1 ||
    { cat lines.log >&2; fail "the installed hsr does not draw lines"; }
if compgen -G "$build/python/hsr/_hsr*.so" > /dev/null; then
    "$python" -c 'import hsr, os; print(hsr.__file__); print(sorted({os.path.dirname(p["path"]) for p in hsr.plugins()}))' \
        > python.txt 2>&1 || { cat python.txt >&2; fail "python3 does not import the installed hsr"; }
    grep -q "^$prefix/lib/python3[.0-9]*/site-packages/hsr/__init__.py\$" python.txt ||
        fail "python3 imports hsr from $(head -n 1 python.txt), not from the user site under $prefix"
    grep -qxF "['$prefix/lib/hsr/plugins']" python.txt || fail "the installed Python package finds plugins in $(tail -n 1 python.txt)"
fi
echo "install_prefix: $installed plugins found from $work/elsewhere by $prefix/bin/hsr"
