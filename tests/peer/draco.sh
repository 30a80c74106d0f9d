#!/usr/bin/env bash
# Google Draco (Debian's `draco` package: draco_encoder / draco_decoder) on a PLY mesh:
# compressed size and decode speed, for the side-by-side with Java 3D's compressed geometry.
#
#   bash tests/peer/draco.sh MESH.ply QP QN [QG] [--cl LEVEL] [--runs N] [--install]
#
#   QP   -qp position bits; QN  -qn normal bits (octahedral); QG  -qg generic-attribute bits
#        (default 8). 8-bit colours (PLY uchar red/green/blue/alpha) are Draco COLOR
#        attributes and are stored exactly; -qg does not touch them.
#   --cl compression level (default 7, Draco's default; 10 = smallest)
#   --runs N decoder runs to time (default 30)
#   --install  apt-get install draco when draco_encoder is missing
#
# Prints `key value` pairs on two lines (see tests/peer/java3d/README.md):
#   draco MESH qp .. qn .. qg .. cl .. triangles T bytes B bytes_per_triangle B/T
#   decode runs N wall_ms W startup_ms S net_ms W-S net_triangles_per_s T/(W-S)
#          self_ms M self_triangles_per_s T/M
# wall_ms: median wall time of one `draco_decoder -i X.drc -o Y.ply` process (decode +
# writing a binary PLY into a temporary directory); startup_ms: the same for a one-triangle
# mesh with the same attributes and options (process start-up, library loading), runs
# interleaved with the mesh's; net = wall - startup; self_ms: the mean of draco_decoder's
# own "(N ms to decode)" figure (whole milliseconds, so a coarse figure).
set -euo pipefail

usage() { sed -n '5,14p' "$0" >&2; exit 2; }
[ $# -ge 3 ] || usage
mesh=$1 qp=$2 qn=$3
shift 3
qg=8 cl=7 runs=30 install=0
if [ $# -gt 0 ] && [[ $1 != --* ]]; then qg=$1; shift; fi
while [ $# -gt 0 ]; do
    case $1 in
        --cl) cl=$2; shift 2 ;;
        --runs) runs=$2; shift 2 ;;
        --install) install=1; shift ;;
        *) usage ;;
    esac
done

if ! command -v draco_encoder >/dev/null || ! command -v draco_decoder >/dev/null; then
    if [ "$install" = 1 ]; then
        sudo_=""; [ "$(id -u)" -eq 0 ] || sudo_=sudo
        $sudo_ apt-get update -qq >&2 || true
        $sudo_ env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends draco >&2
    else
        echo "draco.sh: draco_encoder/draco_decoder missing (apt-get install draco, or pass --install)" >&2
        exit 1
    fi
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/holo-draco.XXXXXX")
trap 'rm -rf "$work"' EXIT

triangles=$(awk '/^element face/ {print $3; exit}' "$mesh")
[ -n "$triangles" ] || { echo "draco.sh: $mesh: no 'element face' line" >&2; exit 1; }

# A one-triangle mesh with the same header (so the same attributes): start-up cost.
awk -v tiny="$work/tiny.ply" '
    BEGIN { header = 1 }
    header && /^element vertex/ { print "element vertex 3" > tiny; next }
    header && /^element face/   { print "element face 1" > tiny; next }
    header { print > tiny; if ($0 == "end_header") header = 0; next }
    nv < 3 { print > tiny; nv++; next }
    END { print "3 0 1 2" > tiny }
' "$mesh"

opts=(-qp "$qp" -qn "$qn" -qg "$qg" -cl "$cl")
draco_encoder -i "$mesh" -o "$work/mesh.drc" "${opts[@]}" >"$work/enc.log"
draco_encoder -i "$work/tiny.ply" -o "$work/tiny.drc" "${opts[@]}" >/dev/null
bytes=$(stat -c %s "$work/mesh.drc")
calc() { awk "BEGIN { print $* }"; }
printf 'draco %s qp %s qn %s qg %s cl %s triangles %s bytes %s bytes_per_triangle %.4f\n' \
    "$(basename "$mesh")" "$qp" "$qn" "$qg" "$cl" "$triangles" "$bytes" "$(calc "$bytes / $triangles")"

# Decoder processes on the mesh and on the tiny mesh, interleaved (so load changes on a
# shared machine hit both alike); each run timed alone; medians reported.
median() { sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print 0; else if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
one_run() { # $1 .drc, $2 file for wall ms, $3 file for self ms
    local t0 t1 line
    t0=$(date +%s%N)
    line=$(draco_decoder -i "$1" -o "$work/out.ply")
    t1=$(date +%s%N)
    calc "($t1 - $t0) / 1000000" >>"$2"
    [[ $line =~ \(([0-9]+)\ ms\ to\ decode\) ]] && echo "${BASH_REMATCH[1]}" >>"$3"
    return 0
}
draco_decoder -i "$work/mesh.drc" -o "$work/out.ply" >/dev/null # warm the page cache
for _ in $(seq "$runs"); do
    one_run "$work/mesh.drc" "$work/wall" "$work/self"
    one_run "$work/tiny.drc" "$work/wall.tiny" "$work/self.tiny"
done
wall=$(median <"$work/wall")
startup=$(median <"$work/wall.tiny")
self=$(awk '{ s += $1 } END { print NR ? s / NR : 0 }' "$work/self")
net=$(calc "$wall - $startup")
rate() { awk -v t="$1" -v ms="$2" 'BEGIN { if (ms > 0) printf "%.0f", t * 1000 / ms; else printf "n/a" }'; }
printf 'decode runs %s wall_ms %.3f startup_ms %.3f net_ms %.3f net_triangles_per_s %s self_ms %.2f self_triangles_per_s %s\n' \
    "$runs" "$wall" "$startup" "$net" "$(rate "$triangles" "$net")" "$self" "$(rate "$triangles" "$self")"
