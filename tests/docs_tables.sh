#!/usr/bin/env bash
# Checks that the two machine-checkable tables of docs/architecture.md are in step with the tree:
#   <!-- architecture-table: plugins -->      one row per plugin: | kind | `name` | `plugins/<kind>/<name>` |
#   <!-- architecture-table: host-rooms -->   one row per host room: | `host/<room>` | what it holds |
# each table ending at <!-- end architecture-table -->. It fails, naming each, on
#   - a plugin folder plugins/<kind>/<name>/ with no row, or a row whose folder does not exist or whose
#     kind and name are not those of its folder;
#   - a host room, a folder under host/ that holds source files itself (at any depth: host/view/server),
#     with no row, or a row that is not such a folder; and source files directly in host/, outside
#     every room.
#   docs_tables.sh <source dir>
set -euo pipefail
src=$1
cd "$src"
page=docs/architecture.md
status=0
fail() {
    echo "docs_tables: $*" >&2
    status=1
}

# The rows of one table: the cells of each line between its markers, '|'-separated, trimmed.
table_rows() {
    awk -v name="$1" '
        $0 ~ "^<!-- architecture-table: " name " -->[ \t]*$" { inside = 1; next }
        inside && /^<!-- end architecture-table -->/ { inside = 0; found = 1; next }
        inside && /^\|/ {
            if ($0 ~ /^\|[ \t:-]*\|/ && $0 !~ /[A-Za-z]/) next        # the | --- | line
            line = $0
            sub(/^\|[ \t]*/, "", line); sub(/[ \t]*\|[ \t]*$/, "", line)
            n = split(line, cell, /[ \t]*\|[ \t]*/)
            if (header_done != name) { header_done = name; next }  # the header row
            out = cell[1]
            for (i = 2; i <= n; ++i) out = out "\t" cell[i]
            print out
        }
        END { if (!found) exit 3 }
    ' "$page"
}
unquote() { local s=$1; s=${s#\`}; s=${s%\`}; printf '%s' "$s"; }

# ---- plugins ------------------------------------------------------------------------------------
if ! plugin_rows=$(table_rows plugins); then
    fail "$page has no table between <!-- architecture-table: plugins --> and <!-- end architecture-table -->"
    plugin_rows=""
fi
declare -A listed_plugin=()
while IFS=$'\t' read -r kind name dir _; do
    [ -n "${kind:-}" ] || continue
    name=$(unquote "$name")
    dir=$(unquote "$dir")
    dir=${dir%/}
    listed_plugin[$dir]=1
    if [ ! -d "$dir" ]; then
        fail "$page lists plugin '$name' in $dir, but there is no such folder"
    elif [ "$dir" != "plugins/$kind/$name" ]; then
        fail "$page: the row of '$name' ($kind) names the folder $dir, not plugins/$kind/$name"
    fi
done <<< "$plugin_rows"
for dir in plugins/*/*/; do
    [ -d "$dir" ] || continue
    dir=${dir%/}
    kind_name=${dir#plugins/}
    [ -n "${listed_plugin[$dir]:-}" ] ||
        fail "plugin folder $dir is not in the plugin table of $page (add the row | ${kind_name%%/*} | \`${kind_name#*/}\` | \`$dir\` |)"
done
plugin_count=${#listed_plugin[@]}

# ---- host rooms ---------------------------------------------------------------------------------
is_source='.*\.\(c\|cc\|cpp\|cxx\|h\|hpp\|hxx\|inc\|js\|mjs\|html\|css\)'
if ! room_rows=$(table_rows host-rooms); then
    fail "$page has no table between <!-- architecture-table: host-rooms --> and <!-- end architecture-table -->"
    room_rows=""
fi
declare -A listed_room=()
while IFS=$'\t' read -r room _; do
    [ -n "${room:-}" ] || continue
    room=$(unquote "$room")
    room=${room%/}
    listed_room[$room]=1
    if [ ! -d "$room" ]; then
        fail "$page lists host room $room, but there is no such folder"
    elif [ -z "$(find "$room" -maxdepth 1 -type f -regex "$is_source" -print -quit)" ]; then
        fail "$page lists host room $room, but it holds no source files of its own"
    fi
done <<< "$room_rows"
while IFS= read -r room; do
    [ -n "${listed_room[$room]:-}" ] ||
        fail "host folder $room holds source files but is not in the host-room table of $page"
done < <(find host -mindepth 2 -type f -regex "$is_source" -printf '%h\n' | sort -u)
loose=$(find host -maxdepth 1 -type f -regex "$is_source" -printf '%f\n' | sort | tr '\n' ' ' | sed 's/ $//')
[ -z "$loose" ] || fail "source files directly in host/, outside every room of $page: $loose"

if [ "$status" -ne 0 ]; then
    echo "docs_tables: docs/architecture.md and the tree differ (see above); change whichever is wrong" >&2
    exit 1
fi
echo "docs_tables: $plugin_count plugins and ${#listed_room[@]} host rooms, as in docs/architecture.md"
