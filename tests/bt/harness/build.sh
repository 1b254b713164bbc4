#!/usr/bin/env bash
# Build schemalog's BT.CPP harness (tests/bt/harness/harness.cpp) against the real
# BehaviorTree.CPP 4.8.2, whose source ships inside behaviortreepy 0.1.4's PyPI sdist (MIT).
# Nothing of BT.CPP is committed here: the sdist is downloaded from PyPI with pip, the library
# built once (about 70 s on 2 cores) into the cache, the harness compiled when its source
# changed. Idempotent: with everything cached it only checks and prints the binary's path.
#
#   tests/bt/harness/build.sh              prints the harness's path on stdout (last line)
#   tests/bt/harness/build.sh --cache-dir  prints the cache directory it uses, and does nothing else
#
# Cache: $SCHEMALOG_BTCPP_CACHE, else $XDG_CACHE_HOME/schemalog-btcpp, else
# ~/.cache/schemalog-btcpp (as schemalog's own cache, src/schemalog/cache.py). Needs pip, cmake, make, g++
# (with none of cmake/g++ and root or sudo, they are installed with apt-get). Progress goes to
# stderr; exit 1 when something is missing or fails.
set -euo pipefail

HERE="$(cd "$(dirname "$0")" && pwd)"
CACHE="${SCHEMALOG_BTCPP_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/schemalog-btcpp}"
if [ "${1:-}" = "--cache-dir" ]; then echo "$CACHE"; exit 0; fi
VERSION=0.1.4                   # behaviortreepy: BehaviorTree.CPP 4.8.2 inside
SRC="$CACHE/sdist/behaviortreepy-$VERSION/BehaviorTree.CPP"
BUILD="$CACHE/build-$VERSION"
LIB="$BUILD/libbehaviortree_cpp.a"
BIN="$CACHE/harness"
JOBS="${SCHEMALOG_BTCPP_JOBS:-2}"

say() { echo "build.sh: $*" >&2; }

need_tools() {
    local missing=()
    for t in cmake make g++; do command -v "$t" >/dev/null 2>&1 || missing+=("$t"); done
    [ ${#missing[@]} -eq 0 ] && return 0
    say "missing ${missing[*]}; trying apt-get install cmake make g++"
    local sudo=""
    if [ "$(id -u)" -ne 0 ]; then
        command -v sudo >/dev/null 2>&1 && sudo="sudo -n" || { say "not root and no sudo: install cmake and g++"; return 1; }
    fi
    $sudo apt-get update -qq >&2 && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq cmake make g++ >&2
}

mkdir -p "$CACHE"
exec 9>"$CACHE/.lock"                       # one build at a time (pytest workers, CI)
flock 9 2>/dev/null || true

if [ ! -f "$SRC/CMakeLists.txt" ]; then
    say "downloading behaviortreepy==$VERSION's sdist from PyPI"
    mkdir -p "$CACHE/sdist"
    python3 -m pip download --quiet --no-deps --no-binary :all: "behaviortreepy==$VERSION" -d "$CACHE/sdist" >&2
    tar -xzf "$CACHE/sdist/behaviortreepy-$VERSION.tar.gz" -C "$CACHE/sdist"
    [ -f "$SRC/CMakeLists.txt" ] || { say "no BehaviorTree.CPP/ in the sdist"; exit 1; }
fi

if [ ! -f "$LIB" ]; then
    need_tools
    say "building BehaviorTree.CPP (static, Release) in $BUILD"
    cmake -S "$SRC" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DBTCPP_SHARED_LIBS=OFF -DBTCPP_BUILD_TOOLS=OFF \
        -DBTCPP_EXAMPLES=OFF -DBUILD_TESTING=OFF -DBTCPP_GROOT_INTERFACE=OFF -DBTCPP_SQLITE_LOGGING=OFF >&2
    make -C "$BUILD" -j"$JOBS" behaviortree_cpp >&2
fi

# the harness: rebuilt when its source (or the build script) differs from the one it was built from
STAMP="$(cat "$HERE/harness.cpp" "$0" | sha256sum | cut -c1-16)"
if [ ! -x "$BIN" ] || [ "$(cat "$BIN.stamp" 2>/dev/null)" != "$STAMP" ]; then
    need_tools
    say "compiling the harness"
    g++ -std=c++17 -O1 -I"$SRC/include" -I"$SRC/3rdparty" "$HERE/harness.cpp" -o "$BIN.tmp" \
        "$LIB" "$BUILD/3rdparty/tinyxml2/libtinyxml2.a" "$BUILD/3rdparty/minitrace/libminitrace.a" \
        "$BUILD/3rdparty/lexy/src/liblexy_file.a" -lpthread -ldl 2> >(grep -v "^/usr/bin/ld: warning" >&2)
    mv "$BIN.tmp" "$BIN"
    echo "$STAMP" > "$BIN.stamp"
fi
echo "$BIN"
