#!/usr/bin/env bash
# The same scene in the browser and natively, side by side in one run (docs/web.md, "Browser
# against native"): for each crowd size, the page in Debian's Chromium (software WebGL 2:
# SwiftShader) in a window of a virtual X server (headless Chromium draws no frames without
# virtual time), its statistics logged by the page after SECONDS measured (?bench; frames/s
# from the frame interval, CPU milliseconds of a frame's code, frames after the first 2), with
# the GL state contract on and off (?restore=0); then web_reference playing the same scene
# natively on an OpenGL ES context (llvmpipe) for 30 frames (CPU: update and draw calls; frame:
# to the read-back, which waits for the GPU). Builds what it needs first.
# Usage: scripts/web_bench.sh [SECONDS] [SIZES] (default 15 and "300 1000")
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-15}"
sizes="${2:-300 1000}"
bash "$root/scripts/web.sh" >/dev/null 2>&1
cd "$root"
cmake --build --preset release --target web_reference >/dev/null
reference=build/release/examples/web_demo/web_reference
port="$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
python3 -m http.server "$port" --bind 127.0.0.1 --directory build/web/site >/dev/null 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true' EXIT
sleep 1
browser() {  # $1 characters, $2 extra query; prints the page's statistics line.
  timeout $((seconds * 4 + 60)) xvfb-run -a -s "-screen 0 1280x800x24" chromium --no-sandbox \
    --use-angle=swiftshader --enable-unsafe-swiftshader --window-size=960,640 --no-first-run \
    --enable-logging=stderr --v=0 "http://127.0.0.1:$port/index.html?count=$1&bench=$seconds$2" \
    2>&1 | grep -m1 -o 'si web demo: bench [^"]*' | sed 's/si web demo: bench //' || true
}
summary='s/.*| \([0-9.]*\) frames\/s, CPU \([0-9.]*\) ms a frame (mean of \([0-9]*\)).*/\1 frames\/s, CPU \2 ms (\3 frames)/p'
printf '%-10s | %-36s | %-36s | %-36s\n' characters "browser" "browser, state contract off" "native (ES profile, llvmpipe)"
for n in $sizes; do
  on="$(browser "$n" "" | sed -n "$summary")"
  off="$(browser "$n" "&restore=0" | sed -n "$summary")"
  native="$("$reference" --palette build/web/default.sipal --instances "$n" --step 0 \
    --bench 30 |
    sed -n 's/.*frames: CPU \([0-9.]*\) ms a frame, frame [0-9.]* ms (\([0-9.]*\) frames\/s).*/\2 frames\/s, CPU \1 ms (30 frames)/p')"
  printf '%-10s | %-36s | %-36s | %-36s\n' "$n" "${on:-no statistics}" "${off:-no statistics}" "$native"
done
