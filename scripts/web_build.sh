#!/usr/bin/env bash
# The page's build, shared by scripts/web.sh and the browser test (tests/web/browser_test.sh):
# bakes the embedded character's palette with the native si-bake (again only when si-bake is
# newer than it), then configures and builds the page with Debian's Emscripten; the page is
# BUILD_DIR/site. Installs nothing (scripts/deps.sh does).
# Usage: scripts/web_build.sh SI_BAKE PALETTE BUILD_DIR
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
si_bake="$1"; palette="$2"; build="$3"
mkdir -p "$(dirname "$palette")"
if [ ! -f "$palette" ] || [ "$si_bake" -nt "$palette" ]; then
  "$si_bake" --embedded -o "$palette" >/dev/null
fi
# Debian's emcc runs its JavaScript optimizer on Debian's node-acorn (docs/web.md).
export NODE_PATH="/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}"
# The native build's flags (sanitizers, warnings) are not the page's.
env -u CFLAGS -u CXXFLAGS -u LDFLAGS emcmake cmake -S "$root" -B "$build" -G Ninja \
  -DCMAKE_BUILD_TYPE=Release -DSI_WEB_PALETTE="$palette" >/dev/null
cmake --build "$build" --target crowd_web
