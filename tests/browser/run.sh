#!/usr/bin/env bash
# ctest's `viewer_in_browser` test: installs playwright-core from the lockfile if it is missing
# (npm ci, from npm's cache when it has it), then drives Debian's chromium through the hsr view page
# (viewer.test.mjs). Skips (exit 77) without node, npm or chromium, or when npm ci cannot install.
#   run.sh HSR_BINARY SOURCE_DIR [SCREENSHOT_DIR]
# The screenshots go to SCREENSHOT_DIR; with SOURCE_DIR/docs/images they refresh the docs' pictures.
# With HSR_BROWSER_TEST_REQUIRED=1 (setup.sh test sets it) a reason to skip is a failure instead.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
skip() {
    echo "$1"
    [ "${HSR_BROWSER_TEST_REQUIRED:-0}" = 1 ] && exit 1
    exit 77
}
for tool in node npm /usr/bin/chromium; do
    command -v "$tool" > /dev/null || skip "skipped: $tool is not installed (bash setup.sh installs it)"
done
if [ ! -d "$here/node_modules/playwright-core" ]; then
    (cd "$here" && npm ci --prefer-offline --no-audit --no-fund --loglevel=error) ||
        skip "skipped: npm ci could not install playwright-core from the lockfile (no registry, no cache)"
fi
exec node "$here/viewer.test.mjs" "$@"
