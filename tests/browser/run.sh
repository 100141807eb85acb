#!/usr/bin/env bash
# ctest's `viewer_in_browser` test: installs playwright-core from the lockfile if it is missing
# (npm ci, from npm's cache when it has it), then drives Debian's chromium through the hsr view page
# (viewer.test.mjs). Skips (exit 77) without node, npm or chromium, or when npm ci cannot install.
#   run.sh HSR_BINARY SOURCE_DIR [SCREENSHOT_DIR]
# The screenshots go to SCREENSHOT_DIR; with SOURCE_DIR/docs/images they refresh the docs' pictures.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
for tool in node npm /usr/bin/chromium; do
    command -v "$tool" > /dev/null || { echo "skipped: $tool is not installed (bash setup.sh installs it)"; exit 77; }
done
if [ ! -d "$here/node_modules/playwright-core" ]; then
    (cd "$here" && npm ci --prefer-offline --no-audit --no-fund --loglevel=error) ||
        { echo "skipped: npm ci could not install playwright-core from the lockfile (no registry, no cache)"; exit 77; }
fi
exec node "$here/viewer.test.mjs" "$@"
