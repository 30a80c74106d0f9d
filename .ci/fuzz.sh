#!/usr/bin/env bash
# Fuzz the .holo reader for a bounded time ($1 seconds, default 120), seeded
# with the frozen test vectors and a few generated files. Exits non-zero on a
# crash; the crashing input is left in fuzz/artifacts/read/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-120}"
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
corpus=fuzz/corpus/read
mkdir -p "$corpus"
cp fixtures/v1.0/*.holo "$corpus/"
# A few more seeds: patterns of both layouts, small enough to mutate.
cargo run --quiet --release -p holo-cli -- pattern --layout mark1 --kind checkerboard --compression piz -o "$corpus/mark1-piz.holo" --force >/dev/null
cargo run --quiet --release -p holo-cli -- pattern --layout mark1 --kind view-ramp --compression rle --f32 -o "$corpus/mark1-rle.holo" --force >/dev/null
# cargo-fuzz needs nightly flags (-Z sanitizer); the stable toolchain allows them with RUSTC_BOOTSTRAP.
cd fuzz
RUSTC_BOOTSTRAP=1 cargo fuzz run read corpus/read -- -max_total_time="$seconds" -rss_limit_mb=4096 -max_len=65536
