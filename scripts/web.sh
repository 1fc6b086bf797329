#!/usr/bin/env bash
# The crowd in a browser: installs what is missing (Debian's emscripten among it), bakes the
# embedded character's palette with the native si-bake, and builds the page with Emscripten into
# build/web/site (index.html, crowd_web.js, crowd_web.wasm: a static folder any web server
# serves). --serve then serves it on http://127.0.0.1:PORT/ (8080 unless given). docs/web.md
# says what the page does; tests/web/browser_test.sh opens it in headless Chromium.
# Usage: scripts/web.sh [--serve [PORT]]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
serve=0
port=8080
while [ $# -gt 0 ]; do
  case "$1" in
    --serve) serve=1; if [ $# -gt 1 ] && [[ "$2" =~ ^[0-9]+$ ]]; then port="$2"; shift; fi ;;
    -h|--help) sed -n '2,7p' "$0"; exit 0 ;;
    *) echo "web.sh: unknown argument $1 (--serve [PORT])" >&2; exit 2 ;;
  esac
  shift
done
bash "$root/scripts/deps.sh"
cd "$root"
cmake --preset release >/dev/null
cmake --build --preset release --target si-bake
bash scripts/web_build.sh build/release/tools/si_bake/si-bake "$root/build/web/default.sipal" \
  build/web
echo "web.sh: the page is build/web/site/index.html"
if [ "$serve" -eq 1 ]; then
  echo "web.sh: serving on http://127.0.0.1:$port/ (Ctrl-C stops)"
  exec python3 -m http.server "$port" --bind 127.0.0.1 --directory build/web/site
fi
