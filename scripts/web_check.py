#!/usr/bin/env python3
"""The web page in headless Chromium, checked against aograph-embed's native result.

Usage: web_check.py SITE NATIVE_DIR [--gltf FILE.glb] [--screenshot PNG [--screenshot-query QUERY]]

Serves SITE (scripts/web-build.sh's output) on a loopback port, opens
index.html?test=<techniques> in headless Chromium (WebGPU on its SwiftShader adapter), and takes
the page's reports (POST /report, one per technique). NATIVE_DIR holds native.json from the
native_ao example: the same scene, camera, size, frames and technique order on a native device.
Each technique must render with no WebGPU validation error, be dark in the crease and about 1 on
open floor, and have a mean within 0.01 of the native mean. A failure names the technique and
the browser's message. With --gltf, the page also fetches FILE.glb (served from SITE), loads it
with aograph's importer and must draw it with gtao: no error, some pixel occluded, the sky
exactly 1. With --screenshot, also saves a picture of the interactive page (its
query string QUERY, default scene=columns: gltf=FILE.glb loads a file served from SITE).
"""
import base64
import http.server
import json
import os
import shutil
import signal
import socketserver
import subprocess
import sys
import tempfile
import threading
import time

SITE, NATIVE = sys.argv[1], sys.argv[2]
SCREENSHOT = sys.argv[sys.argv.index("--screenshot") + 1] if "--screenshot" in sys.argv else None
GLTF = sys.argv[sys.argv.index("--gltf") + 1] if "--gltf" in sys.argv else None
SHOT_QUERY = (sys.argv[sys.argv.index("--screenshot-query") + 1]
              if "--screenshot-query" in sys.argv else "scene=columns")
native = json.load(open(os.path.join(NATIVE, "native.json")))
techniques = list(native["techniques"])
reports = []
done = threading.Event()
drawn = threading.Event()


class Handler(http.server.SimpleHTTPRequestHandler):
    def __init__(self, *args, **kwargs):
        super().__init__(*args, directory=SITE, **kwargs)

    def do_GET(self):
        if self.path.startswith("/hold"):
            # The screenshot's page holds its load event on this until it has drawn.
            drawn.wait(timeout=120)
            self.send_response(204)
            self.end_headers()
            return
        super().do_GET()

    def do_POST(self):
        if self.path.startswith("/drawn"):
            drawn.set()
            self.send_response(204)
            self.end_headers()
            return
        body = self.rfile.read(int(self.headers.get("Content-Length", 0)))
        # Recorded before the page is answered: its next report (or "done") only comes after.
        message = json.loads(body or b"{}")
        if message.get("error") or not message.get("done"):
            reports.append(message)
        if message.get("done") or message.get("error"):
            done.set()
        self.send_response(204)
        self.end_headers()

    def log_message(self, *args):
        pass


def chromium(args, profile):
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if not exe:
        sys.exit("web_check: chromium is not installed (apt-get install chromium)")
    # Background networking off: this machine's network is closed, and Chromium would retry
    # Google's hosts at every start.
    return [exe, "--headless=new", "--no-sandbox", "--enable-unsafe-webgpu",
            "--disable-background-networking",
            "--disable-component-update", "--disable-sync", "--no-first-run",
            "--disable-quic", f"--user-data-dir={profile}"] + args


def run_page(port, query):
    """Opens index.html?QUERY in headless Chromium until the page reports it is done (or
    300 s pass); returns whether it finished, and the reports it sent."""
    done.clear()
    first = len(reports)
    profile = tempfile.mkdtemp(prefix="aograph-chromium-")
    log = os.path.join(profile, "stderr.log")
    # Its own process group: killing it takes Chromium's GPU and renderer processes too.
    browser = subprocess.Popen(chromium([f"http://127.0.0.1:{port}/index.html?{query}"], profile),
                               stdout=subprocess.DEVNULL, stderr=open(log, "w"),
                               start_new_session=True)
    finished = False
    try:
        deadline = time.time() + 300
        while time.time() < deadline and browser.poll() is None:
            if done.wait(timeout=1):
                finished = True
                break
    finally:
        if browser.poll() is None:
            os.killpg(browser.pid, signal.SIGKILL)
        browser.wait()
    if not finished:
        tail = open(log, errors="replace").read()[-2000:]
        how = "exited" if browser.returncode not in (None, -9) else "did not finish in 300 s"
        reports.append({"error": f"Chromium {how} on ?{query}; the end of its log:\n{tail}"})
    shutil.rmtree(profile, ignore_errors=True)
    return finished, reports[first:]


socketserver.TCPServer.allow_reuse_address = True
with socketserver.ThreadingTCPServer(("127.0.0.1", 0), Handler) as server:
    port = server.server_address[1]
    threading.Thread(target=server.serve_forever, daemon=True).start()
    started = time.time()
    finished, technique_reports = run_page(port, f"test={','.join(techniques)}")
    seconds = time.time() - started
    gltf_run = run_page(port, f"test=gtao&gltf={GLTF}") if GLTF else None
    if SCREENSHOT:
        profile = tempfile.mkdtemp(prefix="aograph-chromium-")
        try:
            subprocess.run(chromium([f"--screenshot={os.path.abspath(SCREENSHOT)}",
                                     "--window-size=1340,720",
                                     f"http://127.0.0.1:{port}/index.html?present=copy&hold&{SHOT_QUERY}"],
                                    profile),
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=180)
        except subprocess.TimeoutExpired:
            print("web_check: the screenshot timed out after 180 s (not a test failure)")
        shutil.rmtree(profile, ignore_errors=True)
    server.shutdown()

failures = []
by_name = {r.get("technique"): r for r in technique_reports}
for r in technique_reports:
    if r.get("error"):
        failures.append(f"the page failed: {r['error']}")
width, height = native["width"], native["height"]
crease = native["probes"]["crease"]
floor = native["probes"]["floor"]
for t in techniques:
    r = by_name.get(t)
    if r is None:
        failures.append(f"{t}: no report from the page")
        continue
    if r["errors"]:
        failures.append(f"{t}: the browser reported: {' | '.join(r['errors'])}")
        continue
    ao = base64.b64decode(r["ao"])
    if len(ao) != width * height:
        failures.append(f"{t}: {len(ao)} AO bytes, expected {width}x{height}")
        continue
    at = lambda p: ao[p[1] * width + p[0]] / 255.0
    mean = sum(ao) / 255.0 / len(ao)
    n = native["techniques"][t]
    line = (f"{t}: browser mean {mean:.4f} (native {n['mean']:.4f}), crease {at(crease):.3f} "
            f"(native {n['crease']:.3f}), open floor {at(floor):.3f} (native {n['floor']:.3f}), "
            f"wall ms per frame {', '.join(f'{w:.0f}' for w in r['wall_ms'])} on {r['adapter']}")
    print(line)
    timings = r.get("timings")
    if timings is None:
        print(f"  {t}: the browser offers no timestamp-query; wall time only")
    else:
        passes = timings.get("passes") or []
        print(f"  {t}: GPU timestamps at pass boundaries, frame {timings.get('frame')}: "
              + ", ".join(f"{name} {ms:.2f} ms" for name, ms in passes))
        # The device asked for timestamp-query: the technique's own passes must have been timed.
        if not any(name.startswith(t + ".") and ms > 0 for name, ms in passes):
            failures.append(f"{t}: timestamps were on, but no pass of {t} was timed: {passes}")
    # Same frames and arithmetic on two devices (SwiftShader, lavapipe): the means agree to
    # well under 0.01 unless the page ran something else.
    if abs(mean - n["mean"]) > 0.01:
        failures.append(f"{t}: browser mean {mean:.4f} differs from native {n['mean']:.4f} by more than 0.01")
    # Open floor: nothing within R occludes it, so it is exactly 1 (the native run's value).
    if at(floor) != 1.0 or n["floor"] != 1.0:
        failures.append(f"{t}: open floor reads {at(floor):.3f} (native {n['floor']:.3f}), expected 1")
    # The crease is occluded by two walls: visibly darker than open floor.
    if at(crease) > 0.9:
        failures.append(f"{t}: the crease reads {at(crease):.3f}, expected it dark (<= 0.9)")
if gltf_run:
    gltf_finished, gltf_reports = gltf_run
    r = gltf_reports[0] if gltf_reports else {}
    if not gltf_finished or not r.get("ao"):
        failures.append(f"{GLTF} with gtao: no AO came back: {r.get('error') or r.get('errors')}")
    elif r["errors"]:
        failures.append(f"{GLTF} with gtao: the browser reported: {' | '.join(r['errors'])}")
    else:
        ao = base64.b64decode(r["ao"])
        darkest = min(ao) / 255.0
        top = ao[:width]  # the figure stands mid-view: the top row is sky
        print(f"{GLTF} with gtao: darkest {darkest:.3f}, top row (sky) from {min(top) / 255:.3f}")
        if darkest >= 1.0 or min(top) != 255:
            failures.append(f"{GLTF} with gtao: expected occluded pixels and a sky of exactly 1 "
                            f"(darkest {darkest:.3f}, top row from {min(top) / 255:.3f})")
print(f"web_check: {len(techniques)} techniques in headless Chromium in {seconds:.0f} s")
if failures:
    print("web_check: FAILED\n  " + "\n  ".join(failures), file=sys.stderr)
    sys.exit(1)
print("web_check: passed")
