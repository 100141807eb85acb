#!/usr/bin/env bash
# The layers of the code, checked from its #include lines (docs/architecture.md, "Layers"):
#   sdk/  <  framework/  <  host/common/  <  host/render/, host/bench/, host/view/server/  <  host/cli/, python/src/
# A file includes only its own layer and the ones below it; the three rooms of commands do not include
# one another; a plugin includes only the SDK and its own folder; and the modules of the framework
# (a header with its source, named by the file's stem) and of each host room include one another in
# no loop. Prints every breach and fails when there is one. Usage: include_layers.sh SOURCE_DIR
set -euo pipefail
root="${1:?usage: include_layers.sh SOURCE_DIR}"
cd "$root"
status=0
breach() { echo "include_layers: $*" >&2; status=1; }

# The quoted includes of a file, one per line.
includes() { sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$1"; }

sources() { find "$@" -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' \) | sort; }

# Plugins: the SDK's headers and their own folder's files, nothing else.
for file in $(sources plugins); do
    dir=$(dirname "$file")
    for inc in $(includes "$file"); do
        [ -f "sdk/include/$inc" ] || [ -f "$dir/$inc" ] || breach "$file includes \"$inc\": a plugin sees only the SDK (sdk/include) and its own folder"
    done
done

# The SDK includes only itself.
for file in $(sources sdk/include); do
    for inc in $(includes "$file"); do
        [ -f "sdk/include/$inc" ] || [ -f "$(dirname "$file")/$inc" ] || breach "$file includes \"$inc\": the SDK stands alone"
    done
done

# The framework: the SDK and itself, never the host.
framework_edges=$(mktemp)
trap 'rm -f "$framework_edges"' EXIT
for file in $(sources framework); do
    module=$(basename "${file%.*}")
    for inc in $(includes "$file"); do
        if [ -f "framework/include/$inc" ] || [ -f "framework/src/$inc" ]; then
            target=$(basename "${inc%.*}")
            [ "$target" = "$module" ] || echo "$module $target" >> "$framework_edges"
        elif [ ! -f "sdk/include/$inc" ] && [ ! -f "$(dirname "$file")/$inc" ]; then
            breach "$file includes \"$inc\": the framework sees the SDK and itself only"
        fi
    done
done

# The host's rooms: what each may include besides itself.
room_of() {
    case "$1" in
    host/common/*) echo common ;;
    host/render/*) echo render ;;
    host/bench/*) echo bench ;;
    host/view/server/*) echo view/server ;;
    host/cli/*) echo cli ;;
    *) echo "" ;;
    esac
}
allowed() {  # room, included room
    [ "$1" = "$2" ] && return 0
    case "$1" in
    common) return 1 ;;
    render | bench | view/server) [ "$2" = common ] ;;
    cli) return 0 ;;
    esac
}
host_edges=$(mktemp)
trap 'rm -f "$framework_edges" "$host_edges"' EXIT
for file in $(sources host); do
    room=$(room_of "$file")
    [ -n "$room" ] || { breach "$file lies in no room of host/ (common, render, bench, view/server, cli)"; continue; }
    for inc in $(includes "$file"); do
        if [ -f "host/$inc" ]; then
            target_room=$(room_of "host/$inc")
            allowed "$room" "$target_room" || breach "$file ($room) includes \"$inc\" ($target_room): not a room below it"
            echo "${file%.*} host/${inc%.*}" >> "$host_edges"
        elif [ -f "framework/include/$inc" ] || [ -f "sdk/include/$inc" ] || [ -f "$(dirname "$file")/$inc" ]; then
            :
        else
            breach "$file includes \"$inc\": not in host/, the framework or the SDK"
        fi
    done
done

# The Python module (python/src) is a front end like host/cli: it includes every room of the host,
# the framework, the SDK and its own folder.
for file in $(sources python/src); do
    for inc in $(includes "$file"); do
        [ -f "host/$inc" ] || [ -f "framework/include/$inc" ] || [ -f "sdk/include/$inc" ] || [ -f "$(dirname "$file")/$inc" ] ||
            breach "$file includes \"$inc\": not in host/, the framework, the SDK or python/src"
    done
done

# No loops: tsort names the modules of one when there is.
for edges in "$framework_edges" "$host_edges"; do
    if ! loops=$(awk '$1 != $2' "$edges" | tsort 2>&1 >/dev/null); then
        breach "modules that include one another in a loop: $(echo "$loops" | grep -v 'input contains a loop' | sed 's/^tsort: //' | tr '\n' ' ')"
    fi
done

[ "$status" -eq 0 ] && echo "include_layers: sdk < framework < host/common < host/{render,bench,view/server} < host/cli and python/src, no loops"
exit "$status"
