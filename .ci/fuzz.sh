#!/usr/bin/env bash
# Fuzz the .holo reader, the compressed-geometry decoder and the HoloFlick
# reader for a bounded time ($1 seconds in all, default 120, split between
# the three targets),
# seeded with the frozen test vectors and a few generated files. Exits
# non-zero on a crash; the crashing input is left in fuzz/artifacts/<target>/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-120}"
third=$(( seconds / 3 > 0 ? seconds / 3 : 1 ))
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
corpus=fuzz/corpus/read
mkdir -p "$corpus"
cp fixtures/v1.0/*.holo "$corpus/"
# Full parallax (one part per view) and sealed headers.
for f in fixtures/v1.2/*.holo fixtures/v1.3/*.holo; do cp "$f" "$corpus/$(basename "$(dirname "$f")")-$(basename "$f")"; done
# A few more seeds: patterns of both layouts, small enough to mutate.
cargo run --quiet --release -p holo-cli -- pattern --layout mark1 --kind checkerboard --compression piz -o "$corpus/mark1-piz.holo" --force >/dev/null
cargo run --quiet --release -p holo-cli -- pattern --layout mark1 --kind view-ramp --compression rle --f32 -o "$corpus/mark1-rle.holo" --force >/dev/null
# The compressed-geometry target: the hand-made .cg file, and its streams alone
# (the target reads the first byte as the block kind, then the stream).
cg_corpus=fuzz/corpus/cg_decode
mkdir -p "$cg_corpus"
cp fixtures/cg/*.cg fixtures/cg/java3d/*.cg "$cg_corpus/"
# Object 0's stream: 20 bytes at offset 40 (see fixtures/SOURCES.md).
{ printf '\x00'; dd if=fixtures/cg/hand-two-objects.cg bs=1 skip=40 count=20 status=none; } > "$cg_corpus/stream-positions"
# The HoloFlick reader: the frozen movie.
hflk_corpus=fuzz/corpus/hflk_read
mkdir -p "$hflk_corpus"
cp fixtures/holoflick/v1.0/movie.hflk "$hflk_corpus/v1.0-movie.hflk"
cp fixtures/holoflick/v1.1/movie.hflk "$hflk_corpus/v1.1-movie.hflk"
# cargo-fuzz needs nightly flags (-Z sanitizer); the stable toolchain allows them with RUSTC_BOOTSTRAP.
cd fuzz
RUSTC_BOOTSTRAP=1 cargo fuzz run read corpus/read -- -max_total_time="$third" -rss_limit_mb=4096 -max_len=65536
RUSTC_BOOTSTRAP=1 cargo fuzz run cg_decode corpus/cg_decode -- -max_total_time="$third" -rss_limit_mb=2048 -max_len=65536
RUSTC_BOOTSTRAP=1 cargo fuzz run hflk_read corpus/hflk_read -- -max_total_time="$third" -rss_limit_mb=2048 -max_len=65536
