#!/usr/bin/env python3
"""Checks the three.js 3D views of a redpost HTML report in headless Chromium (WebGL on
SwiftShader), driving the browser through chromedriver's W3C WebDriver HTTP protocol.

    scene_check.py REPORT.html --links N [--out-dir DIR] [--min-diff-pixels 200]

For every scene in window.redpostScenes (the page contract): WebGL is on, linkCount() is N,
fkErrorMm() < 0.01, and moving the keyframe slider like a user changes the screenshot where the
arm is (at least --min-diff-pixels pixels in the arm's screen boxes) on a canvas that is not
blank. window.__redpostErrors and the browser console (WARNING, SEVERE) must stay empty.
With --out-dir the screenshots are kept as scene-<i>-a.png (first keyframe) and -b.png (last).
Exit 0 = pass, 1 = fail (FAIL: lines on stderr), 77 = skipped (no chromium or chromedriver).
REDPOST_CHROMIUM / REDPOST_CHROMEDRIVER name other binaries (a path or a command name).
"""
import argparse
import base64
import contextlib
import json
import math
import os
import pathlib
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.dont_write_bytecode = True  # no __pycache__ left in the source tree by a test run
import png_image  # noqa: E402

# Headless Chromium has no GPU here; ANGLE on SwiftShader (a CPU Vulkan) gives it WebGL. It
# falls back to SwiftShader even without these two flags, but then logs a deprecation warning
# (that fallback is going away): naming them keeps WebGL and a clean console.
CHROMIUM_FLAGS = ["--headless=new", "--no-sandbox", "--use-angle=swiftshader",
                  "--enable-unsafe-swiftshader", "--window-size=1366,900", "--hide-scrollbars",
                  "--no-first-run", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync"]
# The one message Chromium itself logs (rarely) with SwiftShader: a performance note from its
# GPU process (source "rendering") after a pixel read-back. It says nothing about the page, so
# it is printed but not failed on; anything else at WARNING or SEVERE fails, page text included.
CHROMIUM_NOTICE = re.compile(r"\]GL Driver Message \(OpenGL, Performance, \w+, \w+\): "
                             r"GPU stall due to ReadPixels$")
VIEWPORT = (1366, 900)
READY_TIMEOUT_S = 60
DIFF_THRESHOLD = 24  # a channel must change by more than this: antialiasing noise stays below


class Fatal(Exception):
    """A failure after which this scene (or the run) cannot go on; the console is still read."""


class WebDriver:
    def __init__(self, port):
        self.base, self.session = f"http://127.0.0.1:{port}", None

    def call(self, method, path, body=None, timeout=90):
        url = self.base + (f"/session/{self.session}" if self.session else "") + path
        req = urllib.request.Request(url, None if body is None else json.dumps(body).encode(),
                                     {"Content-Type": "application/json"}, method=method)
        try:
            with urllib.request.urlopen(req, timeout=timeout) as r:
                return json.load(r)["value"]
        except urllib.error.HTTPError as e:  # W3C errors: {"value": {"error", "message"}}
            try:
                v = json.load(e)["value"]
                msg = f"{v['error']}: {v['message'].splitlines()[0]}"
            except Exception:
                msg = f"HTTP {e.code}"
            raise Fatal(f"WebDriver {method} {path}: {msg}") from None
        except OSError as e:  # refused, reset or timed out: chromedriver or the browser died
            raise Fatal(f"WebDriver {method} {path}: {e}") from None

    def js(self, script, *args, wait=False):
        return self.call("POST", "/execute/async" if wait else "/execute/sync",
                         {"script": script, "args": list(args)})


def find_binary(env, *names):
    if os.environ.get(env):
        return shutil.which(os.environ[env])
    return next((p for p in map(shutil.which, names) if p), None)


def start_driver(driver, work):
    """Starts chromedriver in a process group of its own, so that whatever it starts can be
    ended with it, on a free port, and waits until it is ready."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    log_path = os.path.join(work, "chromedriver.out")
    # TMPDIR: Chromium's own scratch folders (org.chromium.*) go with the work folder.
    with open(log_path, "wb") as log:
        proc = subprocess.Popen([driver, f"--port={port}"], stdin=subprocess.DEVNULL,
                                stdout=log, stderr=log, start_new_session=True,
                                env=dict(os.environ, TMPDIR=work))
    wd, deadline = WebDriver(port), time.time() + 20
    while time.time() < deadline and proc.poll() is None:
        with contextlib.suppress(Fatal):
            if wd.call("GET", "/status", timeout=2).get("ready"):
                return proc, wd
        time.sleep(0.1)
    stop_driver(proc)
    tail = pathlib.Path(log_path).read_text(errors="replace")[-500:].strip()
    raise Fatal(f"chromedriver did not get ready on port {port}: {tail}")


def stop_driver(proc):
    proc.terminate()
    with contextlib.suppress(subprocess.TimeoutExpired):
        proc.wait(5)
    # What is left of the browser chromedriver started, in chromedriver's process group.
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()


# Run in the page; arguments[0] is the scene index.
INFO_JS = """const s = window.redpostScenes[arguments[0]];
return {webgl: s.webgl, expected: s.expectedLinks, frames: s.frameCount, dpr: devicePixelRatio,
        links: s.webgl ? s.linkCount() : null, fk: s.webgl ? s.fkErrorMm() : null,
        bodies: s.webgl ? s.bodyCount() : null};"""
# What a user's drag does: a new value and an input event (not setFrame: the wiring is tested).
SLIDE_JS = """const s = window.redpostScenes[arguments[0]];
s.canvas.scrollIntoView({block: 'center'});
s.slider.value = String(arguments[1]);
s.slider.dispatchEvent(new Event('input', {bubbles: true}));
return Number(s.slider.value);"""
# Two frames: the first may still be the one being composited when the input event came.
TWO_FRAMES_JS = """const done = arguments[arguments.length - 1];
requestAnimationFrame(() => requestAnimationFrame(() => done(true)));"""
# The canvas's drawing area is its bounding rectangle less its CSS border: a border would
# count as content and hide a canvas that draws nothing.
BOXES_JS = """const s = window.redpostScenes[arguments[0]], c = s.canvas;
const r = c.getBoundingClientRect(), x0 = r.left + c.clientLeft, y0 = r.top + c.clientTop;
return {arm: s.armScreenBox(),
        canvas: {x0, y0, x1: x0 + c.clientWidth, y1: y0 + c.clientHeight}};"""


def device_box(b, scale, width, height, what, snap=False):
    """A CSS-pixel box {x0, y0, x1, y1} in whole device pixels, clipped to the screenshot:
    grown outwards, or with snap rounded as Chromium places a canvas at a fractional offset
    (one at y = 406.875 starts on row 407; row 406 is its border)."""
    try:
        v = [float(b[k]) * scale for k in ("x0", "y0", "x1", "y1")]
    except (TypeError, KeyError, ValueError):
        raise Fatal(f"{what} is not a box {{x0, y0, x1, y1}}: {b!r}") from None
    if not all(map(math.isfinite, v)) or v[2] <= v[0] or v[3] <= v[1]:
        raise Fatal(f"{what} is empty or not finite: {b!r}")
    lo, hi = (round, round) if snap else (math.floor, math.ceil)
    return (max(0, lo(v[0])), max(0, lo(v[1])), min(width, hi(v[2])), min(height, hi(v[3])))


def shot(wd, i, frame, dpr, out_dir, tag):
    """Shows keyframe `frame` through the slider; returns (arm box, canvas box, PngImage)."""
    got = wd.js(SLIDE_JS, i, frame)
    if got != frame:
        raise Fatal(f"scene {i}: the slider holds {got} after being set to keyframe {frame}")
    wd.js(TWO_FRAMES_JS, wait=True)
    boxes = wd.js(BOXES_JS, i)
    png = base64.b64decode(wd.call("GET", "/screenshot"))
    if out_dir:
        with open(os.path.join(out_dir, f"scene-{i}-{tag}.png"), "wb") as f:
            f.write(png)
    try:  # pure-Python decoding is slow: only down to the canvas's last row
        img = png_image.decode(png, max_rows=math.ceil(boxes["canvas"]["y1"] * dpr))
    except ValueError as e:
        raise Fatal(f"scene {i}: cannot decode screenshot {tag}: {e}") from None
    h = len(img.rows)
    canvas = device_box(boxes["canvas"], dpr, img.width, h, f"scene {i}: the canvas", snap=True)
    return device_box(boxes["arm"], dpr, img.width, h, f"scene {i}: armScreenBox()"), canvas, img


def top_colour_share(img, box):
    """The share of the box that its most common colour covers (every second pixel and row)."""
    x0, y0, x1, y1 = box
    counts = {}
    for row in img.rows[y0:y1:2]:
        for j in range(x0 * img.bpp, x1 * img.bpp, 2 * img.bpp):
            px = row[j:j + 3]
            counts[px] = counts.get(px, 0) + 1
    return max(counts.values()) / sum(counts.values()) if counts else 1.0


def changed_pixels(a, b, box):
    x0, y0, x1, y1 = box
    bpp, n = a.bpp, 0
    for ra, rb in zip(a.rows[y0:y1], b.rows[y0:y1]):
        ra, rb = ra[x0 * bpp:x1 * bpp], rb[x0 * bpp:x1 * bpp]
        if ra != rb:
            n += sum(1 for j in range(0, len(ra), bpp)
                     if max(abs(ra[j + c] - rb[j + c]) for c in range(3)) > DIFF_THRESHOLD)
    return n


def fmt(v):
    return f"{v:.3g}" if isinstance(v, float) else repr(v)


def check_scene(wd, i, args, fails, stats):
    info = wd.js(INFO_JS, i)
    fk, frames = info["fk"], info["frames"]
    print(f"scene {i}: webgl={info['webgl']} links={info['links']} (page told "
          f"{info['expected']}, --links {args.links}) keyframes={frames} fk error={fmt(fk)} mm")
    if info["webgl"] is not True:
        fails.append(f"scene {i}: the page has no WebGL (the browser flags should give it)")
        return
    if info["links"] != args.links:
        fails.append(f"scene {i}: {info['links']} link solids in the scene, expected "
                     f"{args.links} (the page was told {info['expected']})")
    if args.bodies is not None and info["bodies"] != args.bodies:
        fails.append(f"scene {i}: {info['bodies']} bodies of the collision check in the scene, "
                     f"expected {args.bodies}")
    if not isinstance(fk, (int, float)) or not fk < 0.01:  # `not <` also catches NaN (null)
        fails.append(f"scene {i}: forward kinematics is {fmt(fk)} mm off the C++ TCP "
                     "(limit 0.01 mm)")
    if not isinstance(frames, int) or frames < 2:
        fails.append(f"scene {i}: frameCount is {frames!r}, needs an integer >= 2")
        return
    dpr = float(info["dpr"] or 1)
    arm_a, canvas, a = shot(wd, i, 0, dpr, args.out_dir, "a")
    arm_b, canvas_b, b = shot(wd, i, frames - 1, dpr, args.out_dir, "b")
    if canvas != canvas_b:  # the diff would then show the scrolling, not the arm
        raise Fatal(f"scene {i}: the canvas moved between the screenshots: {canvas}, {canvas_b}")
    # One pixel in from the edges: page showing around a canvas that draws nothing must not
    # count as content (a one-pixel frame is 0.4 % of an 800x450 canvas).
    inner = (canvas[0] + 1, canvas[1] + 1, canvas[2] - 1, canvas[3] - 1)
    for tag, img in (("a", a), ("b", b)):
        share = top_colour_share(img, inner)
        if share > 0.995:
            fails.append(f"scene {i}: screenshot {tag} is blank on the canvas "
                         f"({100 * share:.2f} % one colour)")
    # Where the moving arm must show: the union of both arm boxes, clipped to the canvas.
    box = (max(canvas[0], min(arm_a[0], arm_b[0])), max(canvas[1], min(arm_a[1], arm_b[1])),
           min(canvas[2], max(arm_a[2], arm_b[2])), min(canvas[3], max(arm_a[3], arm_b[3])))
    if box[2] <= box[0] or box[3] <= box[1]:
        fails.append(f"scene {i}: the arm boxes {arm_a}, {arm_b} are outside the canvas {canvas}")
        return
    n = changed_pixels(a, b, box)
    print(f"scene {i}: keyframes 0 -> {frames - 1}: {n} pixels changed in the arm box "
          f"{box[2] - box[0]}x{box[3] - box[1]} at ({box[0]}, {box[1]})")
    if n < args.min_diff_pixels:
        fails.append(f"scene {i}: moving the slider from keyframe 0 to {frames - 1} changed "
                     f"{n} pixels where the arm is, expected at least {args.min_diff_pixels}")
    stats.append((info["links"], fk, n))


def read_errors(wd, fails):
    errors = wd.js("return window.__redpostErrors;")
    if not isinstance(errors, list):
        fails.append("the page has no window.__redpostErrors array")
    fails.extend(f"page error: {e}" for e in errors or [])
    try:
        log = wd.call("POST", "/se/log", {"type": "browser"})
    except Fatal:  # chromedrivers older than the W3C-mode /se/ routes have the legacy one
        log = wd.call("POST", "/log", {"type": "browser"})
    for entry in log:
        level, source, msg = entry.get("level"), entry.get("source"), entry.get("message", "")
        if level not in ("WARNING", "SEVERE"):
            continue
        if source == "rendering" and CHROMIUM_NOTICE.search(msg):
            print(f"note: Chromium's own notice, not failed on: {msg}")
        else:
            fails.append(f"console {level} ({source}): {msg}")


def run_checks(wd, args, profile):
    fails, stats = [], []
    try:
        options = {"binary": args.browser, "args": CHROMIUM_FLAGS + [f"--user-data-dir={profile}"]}
        caps = {"browserName": "chrome", "goog:chromeOptions": options,
                "goog:loggingPrefs": {"browser": "ALL"},
                "timeouts": {"pageLoad": 60000, "script": 30000}}
        wd.session = wd.call("POST", "/session",
                             {"capabilities": {"alwaysMatch": caps}})["sessionId"]
        # Headless Chromium still has a window frame: --window-size is the outer size and
        # leaves a 1366x757 viewport. Growing the window by the frame gives the page 1366x900.
        fw, fh = wd.js("return [outerWidth - innerWidth, outerHeight - innerHeight];")
        wd.call("POST", "/window/rect", {"width": VIEWPORT[0] + fw, "height": VIEWPORT[1] + fh})
        wd.call("POST", "/url", {"url": pathlib.Path(args.html).resolve().as_uri()})
        deadline, state = time.time() + READY_TIMEOUT_S, {}
        while time.time() < deadline:
            state = wd.js("const d = document.documentElement.dataset;"
                          "return {ready: d.sceneReady, error: d.sceneError,"
                          " n: Array.isArray(window.redpostScenes) ? redpostScenes.length : -1};")
            if state["error"] is not None or state["ready"] is not None:
                break
            time.sleep(0.1)
        if state.get("error") is not None:
            raise Fatal(f"the page reports a scene error: {state['error']}")
        if state.get("ready") is None:
            raise Fatal(f"the page did not set data-scene-ready within {READY_TIMEOUT_S} s")
        if state["n"] < 1:
            raise Fatal("window.redpostScenes is missing or empty")
        for i in range(state["n"]):
            try:
                check_scene(wd, i, args, fails, stats)
            except Fatal as e:  # one broken scene need not hide what the others show
                fails.append(str(e))
    except Fatal as e:
        fails.append(str(e))
    if wd.session:  # the console tells most about what went wrong: read it in every case
        try:
            read_errors(wd, fails)
        except Fatal as e:
            fails.append(str(e))
    return fails, stats


def main():
    p = argparse.ArgumentParser(description="Checks the 3D views of a redpost report in "
                                "headless Chromium. Exit 0 pass, 1 fail, 77 skipped.")
    p.add_argument("html", metavar="REPORT.html")
    p.add_argument("--links", type=int, required=True, metavar="N",
                   help="link solids each scene must hold")
    p.add_argument("--bodies", type=int, metavar="N",
                   help="the bodies of the collision check each scene must draw")
    p.add_argument("--out-dir", metavar="DIR",
                   help="keep the screenshots there as scene-<i>-a.png and scene-<i>-b.png")
    p.add_argument("--min-diff-pixels", type=int, default=200, metavar="N",
                   help="changed pixels needed where the arm is (default 200)")
    args = p.parse_args()
    args.browser = find_binary("REDPOST_CHROMIUM", "chromium", "chromium-browser")
    driver = find_binary("REDPOST_CHROMEDRIVER", "chromedriver")
    if not args.browser or not driver:
        print(f"SKIP: {'chromedriver' if args.browser else 'chromium'} is not installed "
              "(apt-get install chromium chromium-driver)")
        return 77
    if not os.path.isfile(args.html):
        print(f"FAIL: no report at {args.html}", file=sys.stderr)
        return 1
    if args.out_dir:
        os.makedirs(args.out_dir, exist_ok=True)
    # A test runner's SIGTERM (a timeout) must still run the cleanup below.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit("FAIL: terminated"))
    start, work, proc, wd = time.time(), tempfile.mkdtemp(prefix="scene_check."), None, None
    try:
        proc, wd = start_driver(driver, work)
        fails, stats = run_checks(wd, args, os.path.join(work, "profile"))
    except Fatal as e:
        fails, stats = [str(e)], []
    finally:
        if wd and wd.session:
            with contextlib.suppress(Fatal):
                wd.call("DELETE", "", timeout=15)
        if proc:
            stop_driver(proc)
        shutil.rmtree(work, ignore_errors=True)
    for f in fails:
        print("FAIL:", f, file=sys.stderr)
    if fails:
        return 1
    print(f"PASS: {len(stats)} scene(s); links {', '.join(str(s[0]) for s in stats)}; "
          f"fk error <= {max(s[1] for s in stats):.2g} mm; changed arm pixels "
          f"{', '.join(str(s[2]) for s in stats)}; {time.time() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
