#!/usr/bin/env bash
# Size and decode speed, side by side in one run: Java 3D 1.5.2's compressed geometry
# (its own encoder, public path) at 16/9/6 and 10/8/6 bits (position/colour/normal),
# Deering's ~7 bytes per triangle (paper figure, for reference), Google Draco (Debian's
# draco_encoder/draco_decoder) on the same meshes, and holo when HOLO_CG is set.
#
#   bash tests/peer/java3d/bench.sh [--runs N] [MESH.ply ...]
#
# Without meshes: Spot (../shared/data/mesh_spot_textured_obj, 5,856 triangles, colours
# from its texture), the Utah teapot (../shared/data/mesh_utah_teapot, 6,320 triangles,
# colours from normals) and an icosphere (5,120 triangles), converted with
# tests/peer/mesh_to_ply.py. ../shared/data may be moved with HOLO_SHARED_DATA=DIR; when
# it is missing those two meshes are reported as not run.
#
# bytes/tri = compressed stream bytes / input triangles (.cg: the object's stream, without
# the 32-byte file header, 8-byte block header and directory; .drc: the whole file).
# holo decode: cg_peer time, the same Java-order decode to triangle arrays; `stream` = its
# streaming decoder (triangles handed out as decoded, nothing stored), what holo itself uses.
# Java 3D decode: CgTool time (decoder + GeneralizedStrip.toTriangles in one warm JVM, the
# median pass; `cold` = the first pass of a fresh JVM); triangles/s counts input triangles
# (the stripifier's degenerate ones are decoded too, but not counted).
# Draco decode: draco.sh (median process time minus a one-triangle mesh's, and draco's own
# whole-millisecond figure). Draco -qn 8 (about 2^16 directions, Deering's 6-bit normals
# are about 2^16.7) and 8-bit colours stored exactly.
set -uo pipefail
cd "$(dirname "$0")/../../.."
root=$(pwd)
runs=200
meshes=()
while [ $# -gt 0 ]; do
    case $1 in
        --runs) runs=$2; shift 2 ;;
        *) meshes+=("$1"); shift ;;
    esac
done
data=${HOLO_SHARED_DATA:-$root/../shared/data}

cp=$(bash tests/peer/java3d/build.sh | tail -n 1) || { echo "bench.sh: Java 3D build failed" >&2; exit 1; }
cgtool() { env -u DISPLAY java -Djava.awt.headless=true -cp "$cp" CgTool "$@"; }
command -v draco_encoder >/dev/null || echo "bench.sh: draco missing (apt-get install draco); Draco rows skipped" >&2

work=$(mktemp -d "${TMPDIR:-/tmp}/holo-j3dbench.XXXXXX")
trap 'rm -rf "$work"' EXIT

if [ ${#meshes[@]} -eq 0 ]; then
    spot=$data/mesh_spot_textured_obj
    if [ -r "$spot/spot_triangulated.obj" ]; then
        python3 tests/peer/mesh_to_ply.py obj "$spot/spot_triangulated.obj" "$work/spot.ply" \
            --texture "$spot/spot_texture.png" >&2 && meshes+=("$work/spot.ply")
    else
        echo "bench.sh: $spot missing: Spot NOT run" >&2
    fi
    if [ -r "$data/mesh_utah_teapot/teapot.obj" ]; then
        python3 tests/peer/mesh_to_ply.py obj "$data/mesh_utah_teapot/teapot.obj" "$work/teapot.ply" >&2 &&
            meshes+=("$work/teapot.ply")
    else
        echo "bench.sh: $data/mesh_utah_teapot missing: teapot NOT run" >&2
    fi
    python3 tests/peer/mesh_to_ply.py icosphere 4 "$work/ico4.ply" >&2 && meshes+=("$work/ico4.ply")
fi

# Sum of the objects' stream sizes in a .cg file (block headers: big-endian size at each
# directory offset; the directory offset is at byte 24, the object count at byte 16).
cg_stream_bytes() {
    python3 -c '
import struct, sys
d = open(sys.argv[1], "rb").read()
n, = struct.unpack_from(">i", d, 16)
off, = struct.unpack_from(">q", d, 24)
print(sum(struct.unpack_from(">i", d, struct.unpack_from(">q", d, off + 8 * k)[0])[0] for k in range(n)))' "$1"
}
row() { printf '%-12s %9s  %-8s %-26s %9s %9s %14s %14s\n' "$@"; }
mega() { awk -v x="$1" 'BEGIN { if (x == "n/a" || x == "") print "n/a"; else printf "%.2fM", x / 1e6 }'; }
row mesh triangles codec bits bytes bytes/tri "decode tri/s" "cold/self"
for ply in "${meshes[@]}"; do
    name=$(basename "$ply" .ply)
    tris=$(awk '/^element face/ {print $3; exit}' "$ply")
    for bits in "16 9 6" "10 8 6"; do
        tag=${bits// //}
        cg=$work/$name.${bits// /_}.cg
        if ! cgtool encode "$ply" "$cg" $bits >"$work/enc" 2>/dev/null; then
            row "$name" "$tris" java3d "$tag" FAILED
            continue
        fi
        bytes=$(awk '/^output/ { for (i = 1; i < NF; i++) if ($i == "stream_bytes") print $(i + 1) }' "$work/enc")
        cgtool time "$cg" "$runs" >"$work/time"
        nondeg=$(awk '/^nondegenerate triangles\/s/ {print $6}' "$work/time")
        cold=$(awk '/^cold first pass/ { gsub(/\(/, "", $8); print $8 }' "$work/time")
        row "$name" "$tris" java3d "$tag rgba" "$bytes" "$(awk -v b="$bytes" -v t="$tris" 'BEGIN { printf "%.2f", b / t }')" \
            "$(mega "$nondeg")" "$(mega "$cold") cold"
        if [ -n "${HOLO_CG:-}" ]; then
            if $HOLO_CG encode "$ply" "$work/holo.cg" $bits >/dev/null 2>&1; then
                hb=$(cg_stream_bytes "$work/holo.cg")
                $HOLO_CG time "$work/holo.cg" "$runs" >"$work/htime" 2>/dev/null
                hr=$(awk '/^nondegenerate triangles\/s/ {print $6}' "$work/htime")
                hs=$(awk '/^streaming nondegenerate triangles\/s/ {print $7}' "$work/htime")
                row "$name" "$tris" holo "$tag" "$hb" "$(awk -v b="$hb" -v t="$tris" 'BEGIN { printf "%.2f", b / t }')" "$(mega "$hr")" \
                    "$(mega "$hs") stream"
            else
                row "$name" "$tris" holo "$tag" FAILED
            fi
        fi
        if command -v draco_encoder >/dev/null; then
            qp=${bits%% *}
            bash tests/peer/draco.sh "$ply" "$qp" 8 --runs 30 >"$work/draco"
            db=$(awk '/^draco/ { for (i = 1; i < NF; i++) if ($i == "bytes") print $(i + 1) }' "$work/draco")
            dn=$(awk '/^decode/ { for (i = 1; i < NF; i++) if ($i == "net_triangles_per_s") print $(i + 1) }' "$work/draco")
            ds=$(awk '/^decode/ { for (i = 1; i < NF; i++) if ($i == "self_triangles_per_s") print $(i + 1) }' "$work/draco")
            row "$name" "$tris" draco "qp$qp qn8 rgba8" "$db" "$(awk -v b="$db" -v t="$tris" 'BEGIN { printf "%.2f", b / t }')" \
                "$(mega "$dn")" "$(mega "$ds") self"
        fi
    done
    row "$name" "$tris" deering "paper" "" "~7" "" ""
done
