#!/usr/bin/env python3
# SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
"""What the library's GL queries cost a frame in a browser (docs/web.md, "Queries in a
browser"), side by side in one run: the page (built by scripts/web.sh) in Debian's headless
Chromium, driven through the DevTools protocol (tests/web/devtools.py) in its test mode. Each
WebGL query function of the page's context (getParameter, getIndexedParameter, getError,
isEnabled, ...) is wrapped to count its calls and time them; after 3 warm-up frames, FRAMES
frames are drawn (si_web_step, 1/30 s each) and the means a frame printed: the page's frame
(update and draw calls), the queries' calls and time, and the slowest queries by name.

Variants (the page's query string): the defaults (GL error checks off, the state contract on
without WebGL's round trips); ?checks=1 (glGetError after each call); ?raster=1 (the contract
asks for the cull face mode, front face and colour mask too); ?restore=0 (no contract).
Usage: scripts/web_queries.py [CHARACTERS] [FRAMES]   (default 300 and 5)
"""
import json
import os
import socket
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "web"))
from devtools import Browser  # noqa: E402

VARIANTS = [("defaults", "&checks=0"), ("GL error checks on", "&checks=1"),
            ("contract asks WebGL's round trips", "&checks=0&raster=1"),
            ("contract off", "&checks=0&restore=0")]
WRAP = """(function () {
  var gl = GL.currentContext.GLctx, names = {};
  for (var k in gl) if (typeof gl[k] === 'number' && !(gl[k] in names)) names[gl[k]] = k;
  window.siQueries = {};
  ['getParameter', 'getIndexedParameter', 'getError', 'isEnabled', 'isProgram',
   'getBufferParameter', 'getProgramParameter', 'getTexParameter'].forEach(function (f) {
    var original = gl[f];
    if (!original) return;
    gl[f] = function () {
      var t0 = performance.now(), r = original.apply(gl, arguments);
      var key = f + (typeof arguments[0] === 'number' ? '(' + (names[arguments[0]] || arguments[0]) + ')' : '');
      var e = window.siQueries[key] || (window.siQueries[key] = [0, 0]);
      e[0] += 1; e[1] += performance.now() - t0;
      return r;
    };
  });
})()"""
STEP = """(function (n) {
  var t0 = performance.now();
  for (var i = 0; i < n; ++i) if (Module._si_web_step(1 / 30) != 0) return -1;
  return (performance.now() - t0) / n;
})(%d)"""


def measure(port, count, frames, query):
    browser = Browser("chromium", "/tmp/si_web_queries_chromium.log")
    try:
        browser.open("http://127.0.0.1:%d/index.html?test=1&count=%d%s" % (port, count, query))
        if not browser.wait_for("!!(window.siWeb && window.siWeb.ready)", 240):
            raise RuntimeError("the page did not start: %s" % browser.problems)
        browser.evaluate(STEP % 3)
        browser.evaluate(WRAP)
        frame_ms = browser.evaluate(STEP % frames)
        queries = json.loads(browser.evaluate("JSON.stringify(window.siQueries)"))
    finally:
        browser.close()
    if frame_ms < 0 or browser.problems:
        raise RuntimeError("the page failed: %s" % browser.problems)
    calls = sum(v[0] for v in queries.values()) / frames
    ms = sum(v[1] for v in queries.values()) / frames
    slowest = sorted(queries.items(), key=lambda kv: -kv[1][1])[:3]
    return frame_ms, calls, ms, ", ".join(
        "%s %.0fx %.2f ms" % (k, v[0] / frames, v[1] / frames) for k, v in slowest)


def main():
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 300
    frames = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    subprocess.run(["bash", os.path.join(ROOT, "scripts", "web.sh")], check=True,
                   stdout=subprocess.DEVNULL)
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    server = subprocess.Popen(
        [sys.executable, "-m", "http.server", str(port), "--bind", "127.0.0.1", "--directory",
         os.path.join(ROOT, "build", "web", "site")],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        time.sleep(1)
        print("%d characters, means of %d frames after 3 (Chromium, SwiftShader)" % (count, frames))
        print("| page | frame (update and draw calls) | queries a frame | their time | slowest |")
        print("| --- | --- | --- | --- | --- |")
        for name, query in VARIANTS:
            frame_ms, calls, ms, slowest = measure(port, count, frames, query)
            print("| %s | %.1f ms | %.0f | %.2f ms | %s |" % (name, frame_ms, calls, ms, slowest))
    finally:
        server.kill()
    return 0


if __name__ == "__main__":
    sys.exit(main())
