#!/usr/bin/env bash
# The README's code blocks, as written: every fenced `sh` and `python` block of
# README.md, in order, in one scratch folder that stands for the repository's
# root (its fixtures/ linked in), stopping at the first that fails. A block
# right after an HTML comment `<!-- not run: why -->` is skipped: the comment
# says why, and a reader sees it only in the source.
#
# `holo` is on PATH: HOLO names the binary (default: a release build made
# here); the Python blocks run with PYTHON (default: .venv/bin/python, the
# environment .ci/python.sh makes from the README's install block).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

holo=${HOLO:-}
if [ -z "$holo" ]; then
    cargo build -q --release -p holo-cli
    holo=$root/target/release/holo
fi
python=${PYTHON:-$root/.venv/bin/python}
for tool in "$holo" "$python"; do
    if [ ! -x "$tool" ]; then
        echo "FAIL: $tool is not there (HOLO, PYTHON; .ci/python.sh makes .venv)"
        exit 1
    fi
done

scratch=$(mktemp -d "${TMPDIR:-/tmp}/holo-readme.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
mkdir "$scratch/bin" "$scratch/blocks" "$scratch/work"
ln -s "$(cd "$(dirname "$holo")" && pwd)/$(basename "$holo")" "$scratch/bin/holo"
ln -s "$root/fixtures" "$scratch/work/fixtures"

# One file per block, numbered in order: NN.sh, NN.python, or NN.skip (with why).
awk -v out="$scratch/blocks" '
    other && /^```/ { other = 0; next }
    other { next }
    inside && /^```/ { inside = 0; close(file); next }
    inside { print > file; next }
    /^```(sh|python)[[:space:]]*$/ {
        n++
        lang = substr($0, 4); sub(/[[:space:]]+$/, "", lang)
        file = sprintf("%s/%02d.%s", out, n, skip == "" ? lang : "skip")
        if (skip != "") { print skip > file }
        inside = 1; skip = ""; next
    }
    /^```/ { other = 1; skip = ""; next }
    /^<!--.*-->[[:space:]]*$/ { if ($0 ~ /not run/) skip = $0; next }
    { skip = "" }
' README.md

blocks=("$scratch"/blocks/*)
if [ ! -e "${blocks[0]}" ]; then
    echo "FAIL: README.md has no sh or python blocks"
    exit 1
fi
ran=0
skipped=0
for block in "${blocks[@]}"; do
    name=$(basename "$block")
    case "$name" in
        *.skip)
            echo "== block ${name%.*}: not run, as marked: $(head -n 1 "$block")"
            tail -n +2 "$block" | sed 's/^/    /'
            skipped=$((skipped + 1))
            continue
            ;;
    esac
    echo "== block ${name%.*} (${name#*.}):"
    sed 's/^/    /' "$block"
    case "$name" in
        *.sh) (cd "$scratch/work" && PATH="$scratch/bin:$PATH" bash -euo pipefail "$block") ;;
        *.python) (cd "$scratch/work" && PATH="$scratch/bin:$PATH" "$python" "$block") ;;
    esac
    ran=$((ran + 1))
done
echo "README.md: $ran blocks ran, $skipped not run (marked)"
