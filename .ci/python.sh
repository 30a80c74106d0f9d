#!/usr/bin/env bash
# The Python package (python/): installed exactly as the README's Python
# section says, into a fresh virtual environment, then its tests (pytest),
# which check it against Python OpenEXR and the holo command line.
set -euo pipefail
cd "$(dirname "$0")/.."

# The README's install commands, as written: the fenced block after the
# marker `<!-- python-install -->`.
commands=$(awk '/<!-- python-install -->/ {found = 1; next} found && /^```/ {if (inside) exit; inside = 1; next} inside {print}' README.md)
if [ -z "$commands" ]; then
    echo "FAIL: README.md has no python-install block"
    exit 1
fi
rm -rf .venv
echo "$commands"
bash -euxc "$commands"

.venv/bin/pip install -q --disable-pip-version-check pytest OpenEXR
# The command-line tool the tests run beside the package.
cargo build -q -p holo-cli
HOLO_CLI="$PWD/target/debug/holo" .venv/bin/python -m pytest -q python/tests
# The example a user starts from: mesh → .holo → fringes → what an eye sees.
.venv/bin/python python/examples/mesh_to_view.py --out target/python-example
# The side-by-side read benchmark, once, so it keeps running (figures in BENCHMARKS.md).
.venv/bin/python python/benches/read.py
