#!/usr/bin/env python3
# SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
"""Drives the crowd's page in headless Chromium through the DevTools protocol and checks it
against web_reference (tests/web/browser_test.sh calls this; docs/web.md, "The browser test").

Chromium runs with --remote-debugging-pipe (the protocol's JSON messages, each ended by a NUL
byte, on the browser's file descriptors 3 and 4), so nothing but Python's standard library and
Debian's chromium is needed. The page is opened in its test mode (?test=1&count=N), which draws
a frame only when asked (si_web_step). One script of frames and control moves is played twice:
on the page, through the browser's input events (a mouse drag on the canvas, a wheel turn, the
crowd size select, the LOD slider: the page's own handlers), and by web_reference natively on
an OpenGL ES context. At each check the page's canvas (toDataURL of the frame just drawn) and
its statistics line (#stats) are compared with web_reference's frame and line; a screenshot of
the whole page (NAME.page.png) is kept beside them for people.

Fails on any console error or exception of the page, any browser log entry of level error or
warning (WebGL's warnings among them), a page that does not become ready, or a check that
differs. Usage:
  browser_drive.py CHROMIUM URL WORK_DIR WEB_REFERENCE PALETTE INSTANCES
"""
import base64
import json
import os
import subprocess
import sys
import time

STEP = repr(1.0 / 30.0)  # The page's test step (si::web::kTestStepSeconds), as both parse it.
CENTRE = (480, 270)      # The canvas's centre (960 x 540 at the page's top-left).


def script():
    """The frames and control moves, each an action both sides play (web_reference's names).
    The crowd size is one of the select's options, the LOD scale one of the slider's steps."""
    steps = lambda n: [("--step", STEP)] * n
    return ([("--step", "0")] + steps(2) + [("--check", "first")] +
            [("--drag", "40", "-20"), ("--drag", "25", "-10"), ("--wheel", "-250")] + steps(1) +
            [("--check", "orbit")] +
            [("--set-instances", "100"), ("--lod", "0.2")] + steps(2) +
            [("--check", "controls")])


class Browser:
    """Chromium with the DevTools protocol on a pipe, and one page's session."""

    def __init__(self, chromium, log_path):
        to_browser_r, self.to_browser = os.pipe()
        self.from_browser, from_browser_w = os.pipe()

        def child_fds():  # The protocol's ends at the browser's descriptors 3 and 4.
            os.dup2(to_browser_r, 3)
            os.dup2(from_browser_w, 4)

        self.log = open(log_path, "wb")
        self.process = subprocess.Popen(
            [chromium, "--headless=new", "--no-sandbox", "--use-angle=swiftshader",
             "--enable-unsafe-swiftshader", "--window-size=960,640", "--no-first-run",
             "--remote-debugging-pipe", "about:blank"],
            stdout=self.log, stderr=subprocess.STDOUT, preexec_fn=child_fds,
            # 3 and 4 kept open past the child's closing of the rest (both are open here: the
            # pipes took the lowest free descriptors).
            pass_fds=(3, 4, to_browser_r, from_browser_w))
        os.close(to_browser_r)
        os.close(from_browser_w)
        self.buffer = b""
        self.next_id = 0
        self.session = None
        self.problems = []  # Console errors, exceptions, error and warning log entries.
        self.console = []

    def close(self):
        try:
            self.send("Browser.close", session=False, wait=False)
        except OSError:
            pass
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
        self.log.close()

    def _read_message(self, deadline):
        while b"\0" not in self.buffer:
            if time.monotonic() > deadline:
                raise TimeoutError("no answer from the browser")
            chunk = os.read(self.from_browser, 1 << 20)
            if not chunk:
                raise EOFError("the browser closed its protocol pipe")
            self.buffer += chunk
        message, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(message)

    def _event(self, m):
        method, p = m.get("method"), m.get("params", {})
        if method == "Runtime.consoleAPICalled":
            text = " ".join(str(a.get("value", a.get("description", ""))) for a in p["args"])
            self.console.append(text)
            if p["type"] in ("error", "assert"):
                self.problems.append("console error: " + text)
        elif method == "Runtime.exceptionThrown":
            d = p["exceptionDetails"]
            self.problems.append("exception: " + d.get("exception", {}).get(
                "description", d.get("text", "")))
        elif method == "Log.entryAdded" and p["entry"]["level"] in ("error", "warning"):
            self.problems.append("browser log (%s, %s): %s %s" % (
                p["entry"]["level"], p["entry"]["source"], p["entry"]["text"],
                p["entry"].get("url", "")))

    def send(self, method, params=None, session=True, wait=True, timeout=120):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = self.session
        os.write(self.to_browser, json.dumps(message).encode() + b"\0")
        if not wait:
            return None
        deadline = time.monotonic() + timeout
        while True:
            m = self._read_message(deadline)
            if m.get("id") == self.next_id:
                if "error" in m:
                    raise RuntimeError("%s: %s" % (method, m["error"]))
                return m.get("result", {})
            self._event(m)

    def open(self, url):
        targets = self.send("Target.getTargets", session=False)["targetInfos"]
        page = next(t for t in targets if t["type"] == "page")
        self.session = self.send("Target.attachToTarget",
                                 {"targetId": page["targetId"], "flatten": True},
                                 session=False)["sessionId"]
        for domain in ("Runtime", "Log", "Page"):
            self.send(domain + ".enable")
        # Room for the canvas, the controls and the statistics (the page screenshots).
        self.send("Emulation.setDeviceMetricsOverride",
                  {"width": 980, "height": 640, "deviceScaleFactor": 1, "mobile": False})
        r = self.send("Page.navigate", {"url": url})
        if r.get("errorText"):
            raise RuntimeError("%s: %s" % (url, r["errorText"]))

    def evaluate(self, expression):
        r = self.send("Runtime.evaluate", {"expression": expression, "returnByValue": True})
        if "exceptionDetails" in r:
            raise RuntimeError("%s: %s" % (expression, r["exceptionDetails"]))
        return r["result"].get("value")

    def mouse(self, kind, x, y, **extra):
        params = {"type": kind, "x": x, "y": y, "button": "left"}
        params.update(extra)
        self.send("Input.dispatchMouseEvent", params)


def play_on_page(browser, actions, work):
    """Plays `actions` on the page; writes each check's canvas and statistics into `work`."""
    for action in actions:
        name, values = action[0], action[1:]
        if name == "--step":
            if browser.evaluate("Module._si_web_step(%s)" % values[0]) != 0:
                raise RuntimeError("the page failed drawing a frame")
        elif name == "--drag":  # Pressed at the centre, moved by (dx, dy), released.
            x, y = CENTRE
            dx, dy = int(values[0]), int(values[1])
            browser.mouse("mousePressed", x, y, clickCount=1, buttons=1)
            browser.mouse("mouseMoved", x + dx, y + dy, buttons=1)
            browser.mouse("mouseReleased", x + dx, y + dy, clickCount=1)
        elif name == "--wheel":
            browser.mouse("mouseWheel", CENTRE[0], CENTRE[1], deltaX=0,
                          deltaY=float(values[0]), button="none")
        elif name in ("--set-instances", "--lod"):  # As a person's choice or move fires them.
            element, event = ("count", "change") if name == "--set-instances" else ("lod", "input")
            taken = browser.evaluate(
                "(function (e) { e.value = '%s'; e.dispatchEvent(new Event('%s')); return e.value; "
                "})(document.getElementById('%s'))" % (values[0], event, element))
            if float(taken) != float(values[0]):
                raise RuntimeError("#%s does not take %s (took %s)" % (element, values[0], taken))
        elif name == "--check":
            url = browser.evaluate("document.getElementById('canvas').toDataURL('image/png')")
            with open(os.path.join(work, values[0] + ".png"), "wb") as f:
                f.write(base64.b64decode(url.split(",", 1)[1]))
            with open(os.path.join(work, values[0] + ".txt"), "w") as f:
                f.write(browser.evaluate("document.getElementById('stats').textContent") + "\n")
            # The whole page as a person sees it (controls and statistics), for people only.
            shot = browser.send("Page.captureScreenshot", {"format": "png"})["data"]
            with open(os.path.join(work, values[0] + ".page.png"), "wb") as f:
                f.write(base64.b64decode(shot))


def main():
    chromium, url, work, reference, palette, instances = sys.argv[1:7]
    actions = script()
    browser = Browser(chromium, os.path.join(work, "chromium.log"))
    try:
        browser.open(url)
        deadline = time.monotonic() + 240
        ready = False
        while not ready and not browser.problems and time.monotonic() < deadline:
            time.sleep(0.2)
            ready = browser.evaluate("!!(window.siWeb && window.siWeb.ready)")
        if ready and not browser.problems:
            play_on_page(browser, actions, work)
    finally:
        browser.close()
    for line in browser.console:
        print("page: " + line)
    if browser.problems:
        print("browser test: the page reported problems:\n  " + "\n  ".join(browser.problems))
        return 1
    if not ready:
        print("browser test: the page did not become ready in 240 s; see " + browser.log.name)
        return 1
    command = [reference, "--palette", palette, "--instances", instances]
    for a in actions:
        command += ([a[0], os.path.join(work, a[1] + ".png"), os.path.join(work, a[1] + ".txt")]
                    if a[0] == "--check" else list(a))
    print(" ".join(command))
    return subprocess.run(command).returncode


if __name__ == "__main__":
    sys.exit(main())
