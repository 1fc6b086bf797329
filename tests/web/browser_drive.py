#!/usr/bin/env python3
# SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
"""Drives the crowd's page in headless Chromium through the DevTools protocol and checks it
against web_reference (tests/web/browser_test.sh calls this; docs/web.md, "The browser test").

Chromium is driven through devtools.py (the protocol on a pipe, Python's standard library
only). The page is opened in its test mode (?test=1&count=N), which draws a frame only when
asked (si_web_step). One script of frames and control moves is played twice:
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
import os
import subprocess
import sys

from devtools import Browser

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
        ready = browser.wait_for("!!(window.siWeb && window.siWeb.ready)", 240)
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
