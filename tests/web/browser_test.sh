#!/usr/bin/env bash
# The crowd's page in a real browser (docs/web.md): builds the page with Emscripten into the
# build tree (as scripts/web.sh does), serves it on a free local port, opens it in Debian's
# headless Chromium (software WebGL 2, SwiftShader) in its test mode (?test=4&count=300: a fixed
# 1/30 s step, stopping after 4 frames), takes a screenshot and compares the canvas with
# web_reference's image of the same frame drawn natively on an OpenGL ES context (at most
# 0.5 % of pixels off by more than 8/255, the golden images' tolerance). Fails when the page
# does not finish, on any error it reports (si-web-error), any WebGL warning of the browser or
# any uncaught exception. Exits 77 (ctest: skipped) naming what is missing when emcc or chromium
# is not installed (scripts/deps.sh installs both).
# Usage: browser_test.sh SOURCE_DIR WORK_DIR SI_BAKE WEB_REFERENCE
set -euo pipefail
source_dir="$1"; work="$2"; si_bake="$3"; reference="$4"
frames=4; count=300
for tool in emcc emcmake chromium python3; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "browser test skipped: $tool is not installed (scripts/deps.sh installs it)"
    exit 77
  fi
done
mkdir -p "$work"
bash "$source_dir/scripts/web_build.sh" "$si_bake" "$work/default.sipal" "$work/build" \
  >"$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
site="$work/build/site"
port="$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
python3 -m http.server "$port" --bind 127.0.0.1 --directory "$site" >"$work/server.log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true' EXIT
for _ in $(seq 50); do
  python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$port/index.html')" \
    2>/dev/null && break
  sleep 0.1
done
url="http://127.0.0.1:$port/index.html?test=$frames&count=$count"
shot="$work/page.png"
# Two tries: Chromium's screenshot is of the last frame its compositor presented, which under
# load has been a frame or two behind the page (the page holds its last state for 3 more draws
# against that). A second try is printed, never silent.
for attempt in 1 2; do
  rm -f "$shot"
  timeout 300 chromium --headless=new --no-sandbox --use-angle=swiftshader \
    --enable-unsafe-swiftshader --window-size=960,640 --virtual-time-budget=60000 \
    --screenshot="$shot" --enable-logging=stderr --v=0 "$url" >"$work/chromium.log" 2>&1 || true
  console="$(grep 'CONSOLE' "$work/chromium.log" || true)"
  echo "$console" | sed -e 's/^.*CONSOLE[^"]*"//' -e 's/", source.*$//'
  if echo "$console" | grep -E -q 'si-web-error|WebGL:|Uncaught'; then
    echo "browser test: the page reported errors (above)"
    exit 1
  fi
  if ! echo "$console" | grep -q "si web demo: done, $frames frames"; then
    echo "browser test: the page did not finish $frames frames; Chromium's log:"
    tail -40 "$work/chromium.log"
    exit 1
  fi
  [ -s "$shot" ] || { echo "browser test: no screenshot"; exit 1; }
  if "$reference" --palette "$work/default.sipal" --frames "$frames" --instances "$count" \
    --out "$work/reference.png" --compare "$shot" --max-share 0.005; then
    exit 0
  fi
  [ "$attempt" -eq 1 ] && echo "browser test: the screenshot differs; trying once more"
done
exit 1
