#!/usr/bin/env bash
# Build the Java 3D peer tool (CgTool) against Debian's Java 3D 1.5.2.
#
#   bash tests/peer/java3d/build.sh          install what is missing (apt-get), compile
#   bash tests/peer/java3d/build.sh --check  only report what is installed; never installs
#
# Packages (Debian bookworm): libjava3d-java 1.5.2+dfsg-17 (j3dcore.jar, j3dutils.jar),
# libvecmath-java 1.5.2-7 (vecmath.jar), and a JDK (default-jdk-headless; any javac >= 8).
# libjava3d-java pulls in libjava3d-jni (libj3dcore-ogl.so) as a dependency; the tool never
# loads it (see README.md).
#
# Compiles tests/peer/java3d/src/**/*.java into target/peer/java3d/ and prints, as its last
# line, the class path to run the tool with:
#   java -Djava.awt.headless=true -cp "$(bash tests/peer/java3d/build.sh | tail -n 1)" CgTool ...
set -euo pipefail
cd "$(dirname "$0")/../../.."
root=$(pwd)
check_only=0
[ "${1:-}" = --check ] && check_only=1

jars=(/usr/share/java/j3dcore.jar /usr/share/java/j3dutils.jar /usr/share/java/vecmath.jar)

as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
        echo "build.sh: need root (or sudo) to run: $*" >&2
        return 1
    fi
}

missing() {
    local m=0
    for j in "${jars[@]}"; do [ -r "$j" ] || m=1; done
    command -v javac >/dev/null || m=1
    command -v java >/dev/null || m=1
    return $((1 - m))
}

if missing; then
    if [ "$check_only" = 1 ]; then
        echo "build.sh: Java 3D or a JDK is missing (need ${jars[*]}, java, javac)" >&2
        exit 1
    fi
    pkgs=(libjava3d-java libvecmath-java)
    command -v javac >/dev/null || pkgs+=(default-jdk-headless)
    echo "build.sh: installing ${pkgs[*]}" >&2
    as_root apt-get update -qq >&2 || echo "build.sh: apt-get update failed; trying the install anyway" >&2
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${pkgs[@]}" >&2
    if missing; then
        echo "build.sh: still missing after apt-get install" >&2
        exit 1
    fi
fi
echo "build.sh: $(dpkg-query -W -f='libjava3d-java ${Version}, ' libjava3d-java 2>/dev/null)$(dpkg-query -W -f='libvecmath-java ${Version}, ' libvecmath-java 2>/dev/null)$(javac -version 2>&1)" >&2

out=$root/target/peer/java3d
jcp=$(IFS=:; echo "${jars[*]}")
rm -rf "$out"
mkdir -p "$out"
mapfile -t sources < <(find "$root/tests/peer/java3d/src" -name '*.java' | sort)
# --release 8 keeps the classes loadable by any JRE >= 8.
javac -nowarn --release 8 -encoding UTF-8 -d "$out" -classpath "$jcp" "${sources[@]}" 2>&1 |
    grep -v '^warning: \[options\]' >&2 || true
[ -f "$out/CgTool.class" ] || { echo "build.sh: javac failed" >&2; exit 1; }
echo "$out:$jcp"
