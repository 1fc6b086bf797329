#!/usr/bin/env bash
# The crowd's page in a real browser (docs/web.md, "The browser test"): builds the page with
# Emscripten into the build tree (scripts/web_build.sh, as scripts/web.sh does), serves it on a
# free local port, and has browser_drive.py open it in Debian's headless Chromium (software
# WebGL 2, SwiftShader) through the DevTools protocol: frames and control moves played on the
# page and natively by web_reference, their images and statistics compared, any page error or
# browser warning a failure. Exits 77 (ctest: skipped) naming what is missing when emcc or
# chromium is not installed (scripts/deps.sh installs both).
# Usage: browser_test.sh SOURCE_DIR WORK_DIR SI_BAKE WEB_REFERENCE
set -euo pipefail
source_dir="$1"; work="$2"; si_bake="$3"; reference="$4"
count=300
for tool in emcc emcmake chromium python3; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "browser test skipped: $tool is not installed (scripts/deps.sh installs it)"
    exit 77
  fi
done
mkdir -p "$work"
bash "$source_dir/scripts/web_build.sh" "$si_bake" "$work/default.sipal" "$work/build" \
  >"$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
port="$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
python3 -m http.server "$port" --bind 127.0.0.1 --directory "$work/build/site" \
  >"$work/server.log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true' EXIT
for _ in $(seq 50); do
  python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$port/index.html')" \
    2>/dev/null && break
  sleep 0.1
done
rm -f "$work"/*.png "$work"/*.txt
python3 "$source_dir/tests/web/browser_drive.py" chromium \
  "http://127.0.0.1:$port/index.html?test=1&count=$count" "$work" "$reference" \
  "$work/default.sipal" "$count"
