#!/usr/bin/env bash
# Self-check of the Java 3D peer harness against the frozen interop vectors in
# fixtures/cg/java3d/ (see fixtures/SOURCES.md and README.md in this folder).
#
#   bash tests/peer/java3d/selfcheck.sh           check (CI: .ci/peers.sh runs this)
#   bash tests/peer/java3d/selfcheck.sh --write   regenerate the fixtures (then review the diff)
#
# Checks, each a PASS/FAIL line, ending with `N passed, M failed` (exit 1 on any failure):
#   - mesh_to_ply.py makes the same icosphere PLYs;
#   - Java 3D's encoder (CgTool encode) writes byte-identical .cg files and the same report
#     (bounds, centre, scale, sizes) from them;
#   - Java 3D's decoder (CgTool decode) reads the frozen .cg files to exactly the frozen text,
#     and so does its second, core copy (CgTool decode --core);
#   - the decoded non-degenerate triangles are the PLY's, quantized (cgcheck.py against-ply).
# With HOLO_CG set (a command with CgTool's `encode` and `decode` interface, see README.md):
#   - Java 3D decodes holo's encoding of each PLY to the PLY's quantized triangles (holo's
#     encode report gives the centre and scale), and holo decodes it to the same triangles;
#   - holo decodes every frozen Java 3D .cg to exactly Java 3D's triangles.
set -uo pipefail
cd "$(dirname "$0")/../../.."
root=$(pwd)
fixtures=$root/fixtures/cg/java3d
write=0
[ "${1:-}" = --write ] && write=1

passed=0
failed=0
pass() { passed=$((passed + 1)); echo "PASS $*"; }
fail() { failed=$((failed + 1)); echo "FAIL $*"; }
finish() {
    echo "$passed passed, $failed failed"
    [ "$failed" -eq 0 ]
    exit
}

if ! cp=$(bash tests/peer/java3d/build.sh | tail -n 1); then
    fail "tests/peer/java3d/build.sh (Java 3D 1.5.2 + JDK, CgTool compiled)"
    finish
fi
pass "CgTool built against $(dpkg-query -W -f='libjava3d-java ${Version}' libjava3d-java 2>/dev/null || echo 'Java 3D')"
# No display at all: the decoder and encoder classes must not need one.
cgtool() { env -u DISPLAY java -Djava.awt.headless=true -cp "$cp" CgTool "$@"; }

work=$(mktemp -d "${TMPDIR:-/tmp}/holo-j3d.XXXXXX")
trap 'rm -rf "$work"' EXIT
out=$work
if [ "$write" = 1 ]; then
    mkdir -p "$fixtures"
    out=$fixtures
fi

# name : icosphere level : encode options [; options of the next object appended ...]
vectors=(
    "ico2_16_9_6:2:16 9 6"
    "ico2_10_8_6:2:10 8 6"
    "ico1_16_9_6_nostrip:1:16 9 6 --no-stripify"
    "ico0_multi:0:16 9 6;10 8 6 --no-stripify;16 9 6 --no-colors;16 9 6 --no-colors --no-normals"
)

same() { # what, expected file, actual file
    if cmp -s "$2" "$3"; then pass "$1"; else
        fail "$1 (differs: diff $2 $3)"
        diff "$2" "$3" | head -n 5 | sed 's/^/info   /'
    fi
}

for level in 0 1 2; do
    python3 tests/peer/mesh_to_ply.py icosphere "$level" "$out/ico$level.ply" >/dev/null
    [ "$write" = 1 ] || same "mesh_to_ply.py icosphere $level = fixtures/cg/java3d/ico$level.ply" \
        "$fixtures/ico$level.ply" "$out/ico$level.ply"
done

for v in "${vectors[@]}"; do
    name=${v%%:*}
    rest=${v#*:}
    level=${rest%%:*}
    IFS=';' read -r -a objects <<<"${rest#*:}"
    ply=$out/ico$level.ply
    append=()
    : >"$out/$name.encode.txt"
    for o in "${objects[@]}"; do
        read -r -a opts <<<"$o"
        if ! cgtool encode "$ply" "$out/$name.cg" "${opts[@]}" "${append[@]}" >>"$out/$name.encode.txt" 2>"$work/$name.err"; then
            fail "CgTool encode ico$level.ply ${opts[*]} ${append[*]}: $(head -n 3 "$work/$name.err")"
            continue 2
        fi
        append=(--append)
    done
    [ ${#objects[@]} -gt 1 ] && opts=("${#objects[@]} objects: ${rest#*:}")
    if [ "$write" = 0 ]; then
        same "Java 3D encodes ico$level.ply (${opts[*]}) to the bytes of $name.cg" "$fixtures/$name.cg" "$out/$name.cg"
        same "CgTool encode report = $name.encode.txt" "$fixtures/$name.encode.txt" "$out/$name.encode.txt"
    fi
    # Decode the frozen file (in --write mode: the one just written).
    cg=$fixtures/$name.cg
    cgtool decode --indexed "$cg" >"$work/$name.decoded.txt" 2>"$work/$name.err" ||
        fail "CgTool decode $name.cg: $(head -n 3 "$work/$name.err")"
    if [ "$write" = 1 ]; then
        cp "$work/$name.decoded.txt" "$fixtures/$name.decoded.txt"
    else
        same "Java 3D decodes $name.cg to $name.decoded.txt" "$fixtures/$name.decoded.txt" "$work/$name.decoded.txt"
    fi
    # Java 3D has two copies of the decoder (utils and core); both must agree.
    if cgtool decode --indexed --core "$cg" 2>"$work/$name.err" | cmp -s - "$work/$name.decoded.txt"; then
        pass "Java 3D's core decoder (javax.media.j3d) decodes $name.cg exactly as the utils one"
    else
        fail "Java 3D's core decoder (javax.media.j3d) decodes $name.cg exactly as the utils one $(head -n 2 "$work/$name.err")"
    fi
    if [ "$name" = ico2_16_9_6 ]; then
        cgtool decode --indexed --quantized "$cg" >"$work/$name.quantized.txt"
        if [ "$write" = 1 ]; then cp "$work/$name.quantized.txt" "$fixtures/"; else
            same "Java 3D decodes $name.cg to $name.quantized.txt (integers)" \
                "$fixtures/$name.quantized.txt" "$work/$name.quantized.txt"
        fi
    fi
    if [ ${#objects[@]} -gt 1 ]; then
        : # against-ply and the holo -> Java 3D checks take single-object files
    elif python3 tests/peer/java3d/cgcheck.py against-ply "$fixtures/ico$level.ply" "$fixtures/$name.encode.txt" \
        "$work/$name.decoded.txt" >"$work/$name.check" 2>&1; then
        pass "$name: non-degenerate decoded triangles = ico$level.ply quantized ($(grep -m1 'decoded triangles' "$work/$name.check" | sed 's/^PASS [^:]*: //'))"
    else
        fail "$name: cgcheck.py against-ply"
        sed 's/^/info   /' "$work/$name.check"
    fi
    if [ -n "${HOLO_CG:-}" ] && [ "$write" = 0 ] && [ ${#objects[@]} -eq 1 ]; then
        # holo -> Java 3D: holo encodes the same PLY; Java 3D must decode it to the PLY's
        # triangles quantized as holo's report says, and holo must decode it to the same.
        hcg=$work/$name.holo.cg
        if $HOLO_CG encode "$ply" "$hcg" "${opts[@]}" >"$work/$name.holo.encode.txt" 2>"$work/$name.err" &&
            cgtool decode --indexed "$hcg" >"$work/$name.holo.java.txt" 2>>"$work/$name.err"; then
            pass "Java 3D decodes holo's encoding of ico$level.ply (${opts[*]})"
            if python3 tests/peer/java3d/cgcheck.py against-ply "$ply" "$work/$name.holo.encode.txt" \
                "$work/$name.holo.java.txt" >"$work/$name.check" 2>&1; then
                pass "holo's $name stream, decoded by Java 3D: non-degenerate triangles = ico$level.ply quantized"
            else
                fail "holo's $name stream, decoded by Java 3D: non-degenerate triangles = ico$level.ply quantized"
                sed 's/^/info   /' "$work/$name.check" | head -n 8
            fi
            if $HOLO_CG decode "$hcg" >"$work/$name.holo.holo.txt" 2>"$work/$name.err" &&
                python3 tests/peer/java3d/cgcheck.py compare "$work/$name.holo.java.txt" "$work/$name.holo.holo.txt" \
                    --keep-degenerate >"$work/$name.cmp" 2>&1; then
                pass "holo and Java 3D decode holo's $name stream to the same triangles"
            else
                fail "holo and Java 3D decode holo's $name stream to the same triangles"
                sed 's/^/info   /' "$work/$name.cmp" "$work/$name.err" 2>/dev/null | head -n 8
            fi
            if cmp -s "$hcg" "$fixtures/$name.cg"; then
                echo "info holo's $name.cg is byte-identical to Java 3D's"
            else
                echo "info holo's $name.cg differs from Java 3D's ($(stat -c %s "$hcg") vs $(stat -c %s "$fixtures/$name.cg") bytes)"
            fi
        else
            fail "holo encodes ico$level.ply (${opts[*]}) and Java 3D decodes it: $(head -n 3 "$work/$name.err")"
        fi
    fi
    if [ -n "${HOLO_CG:-}" ] && [ "$write" = 0 ]; then
        # Java 3D -> holo: holo decodes Java 3D's frozen stream to Java 3D's triangles.
        if $HOLO_CG decode "$cg" >"$work/$name.holo.txt" 2>"$work/$name.err" &&
            python3 tests/peer/java3d/cgcheck.py compare "$work/$name.decoded.txt" "$work/$name.holo.txt" \
                --keep-degenerate >"$work/$name.cmp" 2>&1; then
            pass "holo decodes Java 3D's $name.cg to Java 3D's triangles (HOLO_CG=$HOLO_CG)"
        else
            fail "holo decodes Java 3D's $name.cg to Java 3D's triangles (HOLO_CG=$HOLO_CG)"
            sed 's/^/info   /' "$work/$name.cmp" "$work/$name.err" 2>/dev/null | head -n 8
        fi
    fi
done
[ "$write" = 1 ] && echo "info wrote $(ls "$fixtures" | wc -l) files to $fixtures ($(du -cb "$fixtures"/* | tail -n 1 | cut -f1) bytes)"
finish
