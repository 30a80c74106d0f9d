#!/usr/bin/env bash
# Real clients nobody here wrote: .holo files checked by the OpenEXR project's
# own tools in both directions; compressed geometry (.cg) checked with Java 3D
# 1.5.2's own decoder and encoder, and Google Draco run on the same mesh.
#
#   holo -> OpenEXR  examples/peer_vectors.rs writes .holo files and what they
#                    must hold; Debian's `exrheader` must list the holo.*
#                    attributes and channels; tests/peer/openexr_peer.py (PyPI
#                    OpenEXR) must find every attribute, type, probe sample and
#                    digest exactly.
#   frozen vectors   fixtures/v1.*/ (spec §12) read by Python OpenEXR and by
#                    OpenImageIO's oiiotool: seals, digests, the full-parallax
#                    part layout (spec §8), the worked examples' samples, and
#                    every part's statistics as both libraries decode it; and
#                    exrheader lists each full-parallax part's holo.view.
#   a capture        HCI antinous (9 x 9) converted full parallax by the CLI, read
#                    by holo validate, exrheader, Python OpenEXR and oiiotool.
#   OpenEXR -> holo  openexr_peer.py writes .holo files with OpenEXR alone, and
#                    re-encodes holo's files through OpenEXR; examples/peer_read.rs
#                    (HoloFile::open, validate, read_frame) must read them back
#                    exactly; so must `holo validate` once the CLI has it.
#   Java 3D          tests/peer/java3d/selfcheck.sh: Debian's Java 3D 1.5.2 encodes
#                    and decodes the frozen vectors in fixtures/cg/java3d/ exactly
#                    as recorded; with HOLO_CG, holo's .cg streams decode in Java 3D
#                    to the same quantized triangles and Java 3D's .cg files decode
#                    in holo to Java 3D's triangles (tests/peer/java3d/README.md).
#   Draco            tests/peer/draco.sh runs Debian's draco_encoder/draco_decoder.
#
# Usage: .ci/peers.sh            (from anywhere; needs network the first time)
# Environment: PEER_VENV=DIR     virtualenv to use/create (default target/peer-venv)
#              PEERS_KEEP=1      keep the temporary directory of files
#              HOLO_CG=CMD       holo's .cg peer command (default: examples/cg_peer
#                                once it exists)
# Prints one line per check and ends with `N passed, M failed`; exit status 1
# when anything failed.
set -euo pipefail

cd "$(dirname "$0")/.."
root=$(pwd)
venv=${PEER_VENV:-$root/target/peer-venv}
passed=0
failed=0

pass() { passed=$((passed + 1)); echo "PASS $*"; }
fail() { failed=$((failed + 1)); echo "FAIL $*"; }
info() { echo "info $*"; }
finish() {
    echo "$passed passed, $failed failed"
    if [ "$failed" -eq 0 ]; then exit 0; else exit 1; fi
}

as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
        echo "peers.sh: need root (or sudo) to run: $*" >&2
        return 1
    fi
}

# --- tools --------------------------------------------------------------------

if ! command -v exrheader >/dev/null; then
    info "exrheader missing: installing Debian's openexr package"
    as_root apt-get update -qq || info "apt-get update failed; trying the install anyway"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq openexr >/dev/null ||
        info "apt-get install openexr failed"
fi
if command -v exrheader >/dev/null; then
    pass "exrheader available ($(dpkg-query -W -f='openexr ${Version}' openexr 2>/dev/null || echo 'version unknown'))"
else
    fail "exrheader available after installing openexr"
    finish
fi

if ! command -v oiiotool >/dev/null; then
    info "oiiotool missing: installing Debian's openimageio-tools package"
    as_root apt-get update -qq || info "apt-get update failed; trying the install anyway"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq openimageio-tools >/dev/null ||
        info "apt-get install openimageio-tools failed"
fi
if command -v oiiotool >/dev/null; then
    pass "oiiotool available ($(oiiotool --version 2>/dev/null | head -n 1))"
else
    fail "oiiotool available after installing openimageio-tools"
    finish
fi

if [ ! -x "$venv/bin/python" ]; then
    info "creating virtualenv $venv"
    python3 -m venv "$venv" || { fail "python3 -m venv $venv (on Debian: apt-get install python3-venv)"; finish; }
fi
if ! "$venv/bin/python" -m pip install -q --disable-pip-version-check OpenEXR numpy; then
    fail "pip install OpenEXR numpy into $venv"
    finish
fi
py="$venv/bin/python"
pass "Python OpenEXR $("$py" -c 'import OpenEXR; print(OpenEXR.__version__)'), numpy $("$py" -c 'import numpy; print(numpy.__version__)') in $venv"

if cargo build --release -q --example peer_vectors --example peer_read; then
    pass "examples peer_vectors and peer_read built"
else
    fail "cargo build --release --example peer_vectors --example peer_read"
    finish
fi
examples=$(cargo metadata --format-version 1 --no-deps 2>/dev/null |
    "$py" -c 'import json,sys; print(json.load(sys.stdin)["target_directory"])')/release/examples

work=$(mktemp -d "${TMPDIR:-/tmp}/holo-peers.XXXXXX")
if [ "${PEERS_KEEP:-}" = 1 ]; then
    info "files kept in $work"
else
    trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work/holo" "$work/openexr"

# Run a tool that prints PASS/FAIL lines and `N passed, M failed`; add its counts.
run_counted() {
    local what=$1
    shift
    local log="$work/log.$RANDOM" rc=0
    "$@" >"$log" 2>&1 || rc=$?
    local last
    last=$(tail -n 1 "$log")
    if [[ $last =~ ^([0-9]+)\ passed,\ ([0-9]+)\ failed$ ]]; then
        # The tool's own summary becomes an info line; the totals come at the end.
        sed '$d' "$log"
        info "$what: $last"
        passed=$((passed + BASH_REMATCH[1]))
        failed=$((failed + BASH_REMATCH[2]))
        if [ "$rc" -ne 0 ] && [ "${BASH_REMATCH[2]}" -eq 0 ]; then fail "$what: exit status $rc with no failed check"; fi
    else
        cat "$log"
        fail "$what: did not finish (exit status $rc)"
    fi
}

# --- holo -> OpenEXR ----------------------------------------------------------

if "$examples/peer_vectors" "$work/holo" >"$work/vectors.log" 2>&1; then
    pass "peer_vectors wrote $(ls "$work/holo"/*.holo | wc -l) .holo files"
else
    cat "$work/vectors.log"
    fail "peer_vectors ran"
    finish
fi

# exrheader on a file: the holo.* attributes with their EXR types, and exactly
# the channels (and pixel type) the JSON lists, in every part.
exrheader_check() {
    local file=$1 json=$2 name
    name=$(basename "$file")
    local out="$work/exrheader.$name.txt"
    if ! exrheader "$file" >"$out" 2>&1; then
        fail "exrheader $name: exit status non-zero: $(head -n 3 "$out")"
        return
    fi
    local parts
    parts=$("$py" -c 'import json,sys; d=json.load(open(sys.argv[1])); print(len(d.get("parts") or d.get("frames")))' "$json")
    # The format version the JSON expects (1.2, or 1.1 or 1.0 for files written for older readers).
    local version
    version=$("$py" -c '
import json, sys
d = json.load(open(sys.argv[1]))
v = [a["value"] for a in d.get("shared_attributes", []) if a["name"] == "holo.version"]
print(" ".join(map(str, v[0])) if v else "1 [012]")' "$json")
    local pattern
    local patterns=(
        "holo\\.version \\(type v2i\\): \\($version\\)\$"
        'holo\.hololines \(type int\): [0-9]+$'
        'holo\.emitters \(type int\): [0-9]+$'
        'holo\.views \(type int\): [0-9]+$'
        'holo\.digest \(type string\): "sha256:[0-9a-f]{64}"$'
        'holo\.wavelength\.[RGBY] \(type double\): [0-9.e+-]+$'
        'holo\.emitterPitch \(type double\): [0-9.e+-]+$'
        'holo\.viewSpacing \(type string\): "(tan|sin|angle|explicit)"$'
    )
    # A file of format 1.2 seals each part's header (spec §7.2): OpenEXR's tool lists the seal like any attribute.
    if [ "$version" = "1 2" ]; then patterns+=('holo\.headerDigest \(type string\): "sha256:[0-9a-f]{64}"$'); fi
    for pattern in "${patterns[@]}"; do
        local n
        n=$(grep -cE "^$pattern" "$out" || true)
        if [ "$n" -ge "$parts" ]; then pass "exrheader $name: lists '$pattern' ($n×)"; else
            fail "exrheader $name: lists '$pattern' in each of $parts part(s): found $n"; fi
    done
    # Channel lines look like "    v000.R, 16-bit floating-point, sampling 1 1".
    "$py" -c '
import json, sys
d = json.load(open(sys.argv[1]))
if "channels" in d:
    names = d["channels"]
else:
    names = sorted(d["frames"][0]["samples"])
print("\n".join(names))' "$json" >"$work/expected-channels"
    local pixel
    pixel=$("$py" -c 'import json,sys; print({"f16":"16-bit floating-point","f32":"32-bit floating-point"}[json.load(open(sys.argv[1]))["sample_type"]])' "$json")
    grep -E '^    [^ ]+, ' "$out" | sed -E 's/^    ([^,]+), .*/\1/' >"$work/listed-channels"
    local expected_lines
    expected_lines=$(($(wc -l <"$work/expected-channels") * parts))
    if diff <(sort -u "$work/listed-channels") <(sort "$work/expected-channels") >/dev/null &&
        [ "$(wc -l <"$work/listed-channels")" -eq "$expected_lines" ]; then
        pass "exrheader $name: lists the $(wc -l <"$work/expected-channels") channels in each of $parts part(s)"
    else
        fail "exrheader $name: channel list differs from the JSON's ($(wc -l <"$work/listed-channels") lines, $expected_lines expected)"
    fi
    local wrong
    wrong=$(grep -E '^    [^ ]+, ' "$out" | grep -vc ", $pixel, sampling 1 1\$" || true)
    if [ "$wrong" -eq 0 ]; then pass "exrheader $name: every channel $pixel, sampling 1 1"; else
        fail "exrheader $name: $wrong channel line(s) not '$pixel, sampling 1 1'"; fi
}

for f in "$work/holo"/*.holo; do
    exrheader_check "$f" "${f%.holo}.expect.json"
done
info "how exrheader shows rgb_f16_none_cropped.holo (channels v001-v009 left out):"
sed 's/^/info   | /' "$work/exrheader.rgb_f16_none_cropped.holo.txt" | grep -vE '^info   \|     v00[1-9]' || true

run_counted "openexr_peer.py check" "$py" tests/peer/openexr_peer.py check "$work/holo"

# --- the frozen vectors, full parallax among them -----------------------------

run_counted "openexr_peer.py vectors" "$py" tests/peer/openexr_peer.py vectors fixtures/v1.0 fixtures/v1.1 fixtures/v1.2 fixtures/v1.3
for f in fixtures/v1.3/*.holo; do
    out="$work/exrheader.v1.3.$(basename "$f").txt"
    if ! exrheader "$f" >"$out" 2>&1; then
        fail "exrheader $f: exit status non-zero: $(head -n 3 "$out")"
        continue
    fi
    parts=$(grep -c '^holo.view (type v2i)' "$out" || true)
    listed=$(grep -c '^holo.parallax (type string): "full"' "$out" || true)
    if [ "$parts" -gt 0 ] && [ "$parts" -eq "$listed" ]; then
        pass "exrheader $f: $parts parts, each with holo.view (type v2i) and holo.parallax \"full\""
    else
        fail "exrheader $f: holo.view in $parts part(s), holo.parallax \"full\" in $listed"
    fi
done

# --- OpenEXR -> holo ----------------------------------------------------------

run_counted "openexr_peer.py write" "$py" tests/peer/openexr_peer.py write "$work/openexr"
run_counted "openexr_peer.py rewrite" "$py" tests/peer/openexr_peer.py rewrite "$work/holo" "$work/openexr"
for f in "$work/openexr"/*.holo; do
    exrheader_check "$f" "${f%.holo}.peer.json"
done
run_counted "peer_read" "$examples/peer_read" "$work/openexr"

# The CLI, once it offers `holo validate` (exit 0 when valid).
if cargo build --release -q -p holo-cli 2>/dev/null && [ -x "$examples/../holo" ] &&
    "$examples/../holo" validate --help >/dev/null 2>&1; then
    for f in "$work/openexr"/*.holo; do
        if out=$("$examples/../holo" validate "$f" 2>&1); then pass "holo validate $(basename "$f")"; else
            fail "holo validate $(basename "$f"): $out"; fi
    done
else
    info "the holo CLI does not build or has no 'validate' yet: checked with examples/peer_read only"
fi

# --- a real capture in full parallax: HCI antinous, 9 x 9 cameras -------------
# Converted by the holo CLI (the rig as spec'd in tests/cameras/real.rs: the folder
# has no parameters.cfg), then read by holo validate, exrheader, Python OpenEXR and
# oiiotool as the frozen vectors are (seals, every view's digest, the part layout).

data=${HOLO_SHARED_DATA:-$root/../shared/data}
antinous="$data/lightfield_hci_antinous_9x9"
holo_cli="$examples/../holo"
if [ -d "$antinous" ] && [ -x "$holo_cli" ]; then
    mkdir -p "$work/antinous"
    a_out="$work/antinous/antinous-9x9.holo"
    if out=$("$holo_cli" convert cameras "$antinous" --layout pluto2-hogels --baseline 0.06 --focal-px 1462.857 \
        --focus 6.9 --taps 2 -o "$a_out" 2>&1); then
        pass "holo convert cameras antinous (9 x 9) to pluto2-hogels: $(echo "$out" | head -n 1)"
    else
        fail "holo convert cameras antinous: $out"
    fi
    if out=$("$holo_cli" validate "$a_out" 2>&1); then pass "holo validate antinous-9x9.holo"; else
        fail "holo validate antinous-9x9.holo: $out"; fi
    out="$work/exrheader.antinous.txt"
    if exrheader "$a_out" >"$out" 2>&1; then
        parts=$(grep -c '^holo.view (type v2i)' "$out" || true)
        if [ "$parts" -eq 256 ]; then pass "exrheader antinous-9x9.holo: its 256 views, each a part with holo.view"; else
            fail "exrheader antinous-9x9.holo: holo.view in $parts part(s), 256 expected"; fi
    else
        fail "exrheader antinous-9x9.holo: exit status non-zero: $(head -n 3 "$out")"
    fi
    run_counted "openexr_peer.py vectors antinous" "$py" tests/peer/openexr_peer.py vectors "$work/antinous"
elif [ "${HOLO_REQUIRE_DATA:-}" = 1 ]; then
    fail "the HCI antinous capture ($antinous) or the holo CLI ($holo_cli) is missing and HOLO_REQUIRE_DATA=1"
else
    info "SKIPPED the antinous capture: $antinous not present"
fi

# --- Java 3D 1.5.2 compressed geometry (.cg) and Google Draco -------------------
# tests/peer/java3d/: CgTool calls Java 3D's own decoder and encoder classes headless.
# selfcheck.sh installs Java 3D (apt-get, through build.sh), checks Java 3D against the
# frozen vectors in fixtures/cg/java3d/ and, with HOLO_CG set, holo against Java 3D in
# both directions (README.md there). The hook: once examples/cg_peer.rs exists (CgTool's
# `encode`/`decode`/`time` interface over holo's .cg reader and writer), it is built and
# used as HOLO_CG.

if [ -z "${HOLO_CG:-}" ] && [ -f examples/cg_peer.rs ]; then
    if cargo build --release -q --example cg_peer; then
        export HOLO_CG="$examples/cg_peer"
        pass "example cg_peer built: holo's .cg codec checked against Java 3D"
    else
        fail "cargo build --release --example cg_peer"
    fi
fi
[ -n "${HOLO_CG:-}" ] || info "no HOLO_CG (examples/cg_peer.rs): Java 3D checked against the frozen vectors only"
run_counted "java3d selfcheck.sh" bash tests/peer/java3d/selfcheck.sh

if ! command -v draco_encoder >/dev/null || ! command -v draco_decoder >/dev/null; then
    info "draco_encoder missing: installing Debian's draco package"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends draco >/dev/null ||
        info "apt-get install draco failed"
fi
if out=$(bash tests/peer/draco.sh fixtures/cg/java3d/ico2.ply 16 8 --runs 3 2>&1) &&
    grep -q '^draco .* bytes_per_triangle [0-9.]*$' <<<"$out" && grep -q '^decode runs 3 ' <<<"$out"; then
    pass "draco.sh on ico2.ply ($(dpkg-query -W -f='draco ${Version}' draco 2>/dev/null)): $(head -n 1 <<<"$out" | sed 's/.*bytes_per_triangle/bytes\/triangle/')"
else
    fail "draco.sh on fixtures/cg/java3d/ico2.ply: $(tail -n 3 <<<"$out")"
fi

finish
