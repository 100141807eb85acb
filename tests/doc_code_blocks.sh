#!/usr/bin/env bash
# Checks that the code the docs show is the code that is built: a fenced code block right after a
# marker line
#   <!-- file: PATH -->      is the whole of PATH (relative to the source folder), line for line;
#   <!-- excerpt: PATH -->   is a run of consecutive lines of PATH, verbatim (it may be indented less
#                            than in PATH, by the same whitespace on every line).
# In the pages named strict below, every fenced block needs a language, and every C, C++ or CMake
# block needs a marker, so that no example there can drift from what CI builds and runs.
#   doc_code_blocks.sh <source dir>
set -euo pipefail
src=$1
cd "$src"

strict_pages=" docs/writing-a-plugin.md docs/sdk-reference.md "
pages=(README.md docs/*.md docs/algorithms/*.md)

status=0
for page in "${pages[@]}"; do
    strict=0
    [[ "$strict_pages" == *" $page "* ]] && strict=1
    awk -v page="$page" -v strict="$strict" '
    function fail(line, message) { printf "%s:%d: %s\n", page, line, message; failed = 1 }

    # Reads PATH into lines[1..n] (a cache of one file at a time is enough); returns n, or -1.
    function load(path,    line, n, rc) {
        if (path == loaded_path) return loaded_count
        delete lines
        n = 0
        while ((rc = (getline line < path)) > 0) lines[++n] = line
        close(path)
        if (rc < 0) return -1
        loaded_path = path
        loaded_count = n
        return n
    }

    # The block (block[1..count]) against the marker of the block that opened on line `at`.
    function check_block(at,    n, i, s, best, best_start, run, shift, pad) {
        n = load(marker_path)
        if (n < 0) { fail(marker_line, "the marked file " marker_path " does not exist"); return }
        if (marker_kind == "file") {
            for (i = 1; i <= count && i <= n; ++i) {
                if (block[i] != lines[i]) {
                    fail(at + i, "differs from " marker_path " at its line " i ":\n  doc:  " block[i] \
                         "\n  file: " lines[i])
                    return
                }
            }
            if (count != n)
                fail(at, "shows " count " lines but " marker_path " has " n \
                     " (the block must be the whole file; mark a part of it as an excerpt)")
            return
        }
        if (count == 0) { fail(at, "an empty excerpt of " marker_path); return }
        best = 0
        for (s = 1; s + count - 1 <= n; ++s) {
            # The excerpt may sit further left than in the file, by the same whitespace on each line.
            shift = length(lines[s]) - length(block[1])
            if (shift < 0 || substr(lines[s], shift + 1) != block[1]) continue
            pad = substr(lines[s], 1, shift)
            if (pad !~ /^[ \t]*$/) continue
            for (run = 0; run < count; ++run) {
                if (lines[s + run] == pad block[run + 1]) continue
                if (block[run + 1] == "" && lines[s + run] ~ /^[ \t]*$/) continue
                break
            }
            if (run == count) return
            if (run > best) { best = run; best_start = s }
        }
        if (best == 0)
            fail(at + 1, "is not an excerpt of " marker_path ": its first line is not in the file:\n  doc:  " block[1])
        else
            fail(at + best + 1, "is not a verbatim excerpt of " marker_path ": it follows its lines " \
                 best_start "-" (best_start + best - 1) " and then differs:\n  doc:  " block[best + 1] \
                 "\n  file: " (best_start + best <= n ? lines[best_start + best] : "(end of file)"))
    }

    {
        sub(/\r$/, "")
    }

    in_block {
        if ($0 ~ /^[ \t]*```[ \t]*$/) {
            in_block = 0
            if (marker_kind != "") check_block(open_line)
            else if (strict && lang ~ /^(c|h|cpp|hpp|cxx|c\+\+|cmake)$/)
                fail(open_line, "a " lang " block without a <!-- file: PATH --> or <!-- excerpt: PATH --> marker line before it")
            next
        }
        line = $0
        if (substr(line, 1, length(indent)) == indent) line = substr(line, length(indent) + 1)
        block[++count] = line
        next
    }

    /^[ \t]*```/ {
        in_block = 1
        open_line = NR
        count = 0
        delete block
        match($0, /^[ \t]*/)
        indent = substr($0, 1, RLENGTH)
        lang = $0
        sub(/^[ \t]*`+[ \t]*/, "", lang)
        sub(/[ \t].*$/, "", lang)
        lang = tolower(lang)
        if (strict && lang == "") fail(NR, "a code block without a language (sh for commands, text for output)")
        if (pending_line == NR - 1) {
            marker_kind = pending_kind
            marker_path = pending_path
            marker_line = pending_line
        } else {
            marker_kind = ""
        }
        pending_line = 0
        next
    }

    pending_line && pending_line == NR - 1 {
        fail(pending_line, "a marker line not followed by a code block")
        pending_line = 0
    }

    /^[ \t]*<!--[ \t]*(file|excerpt):/ {
        text = $0
        if (text !~ /^[ \t]*<!--[ \t]*(file|excerpt):[ \t]*[^ \t]+[ \t]*-->[ \t]*$/) {
            fail(NR, "a malformed marker line (write <!-- file: PATH --> or <!-- excerpt: PATH -->)")
            next
        }
        sub(/^[ \t]*<!--[ \t]*/, "", text)
        sub(/[ \t]*-->[ \t]*$/, "", text)
        pending_kind = (text ~ /^file:/) ? "file" : "excerpt"
        sub(/^(file|excerpt):[ \t]*/, "", text)
        pending_path = text
        pending_line = NR
    }

    END {
        if (in_block) fail(open_line, "a code block that is never closed")
        if (pending_line) fail(pending_line, "a marker line not followed by a code block")
        exit failed
    }
    ' "$page" || status=1
done

if [ "$status" -ne 0 ]; then
    echo "doc_code_blocks: the code blocks above break the rules at the top of tests/doc_code_blocks.sh" >&2
    exit 1
fi
echo "doc_code_blocks: every marked code block matches its file"
