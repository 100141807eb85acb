#!/usr/bin/env bash
# Runs pytest on the given test files with PYTHON, the interpreter the package was built for;
# skipped (77), with the reason, when PYTHON lacks numpy or pytest. Usage: run_pytest.sh PYTHON FILE...
set -euo pipefail
python="$1"
shift
if ! "$python" -c 'import numpy, pytest' 2>/dev/null; then
    echo "skipped: $python has no numpy or pytest (Debian's python3-numpy and python3-pytest; setup.sh installs them)"
    exit 77
fi
exec "$python" -m pytest -q -p no:cacheprovider -o console_output_style=classic "$@"
