#!/usr/bin/env python3
# SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
"""A small DevTools protocol client for Debian's headless Chromium, on a pipe: the browser test
(browser_drive.py) and scripts/web_queries.py drive the crowd's page with it.

Chromium runs with --remote-debugging-pipe: the protocol's JSON messages, each ended by a NUL
byte, on the browser's file descriptors 3 (to it) and 4 (from it), so nothing but Python's
standard library is needed (no npm package, no downloaded browser). Events seen while waiting
for an answer are kept: console lines, and as problems, console errors, exceptions and browser
log entries of level error or warning (WebGL's warnings among them).
"""
import json
import os
import subprocess
import time


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

    def wait_for(self, expression, seconds):
        """Polls `expression` until it is true (True), a problem is seen or `seconds` pass."""
        deadline = time.monotonic() + seconds
        while not self.problems and time.monotonic() < deadline:
            if self.evaluate(expression):
                return True
            time.sleep(0.2)
        return False

    def mouse(self, kind, x, y, **extra):
        params = {"type": kind, "x": x, "y": y, "button": "left"}
        params.update(extra)
        self.send("Input.dispatchMouseEvent", params)
