#!/usr/bin/env python3
"""The web page in headless Chromium, checked against aograph-embed's native result.

Usage: web_check.py SITE NATIVE_DIR [--screenshot PNG]

Serves SITE (scripts/web-build.sh's output) on a loopback port, opens
index.html?test=<techniques> in headless Chromium (WebGPU on its SwiftShader adapter), and takes
the page's reports (POST /report, one per technique). NATIVE_DIR holds native.json from the
native_ao example: the same scene, camera, size, frames and technique order on a native device.
Each technique must render with no WebGPU validation error, be dark in the crease and about 1 on
open floor, and have a mean within 0.01 of the native mean. A failure names the technique and
the browser's message. With --screenshot, also saves a picture of the interactive page.
"""
import base64
import http.server
import json
import os
import shutil
import socketserver
import subprocess
import sys
import tempfile
import threading
import time

SITE, NATIVE = sys.argv[1], sys.argv[2]
SCREENSHOT = sys.argv[sys.argv.index("--screenshot") + 1] if "--screenshot" in sys.argv else None
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
        self.send_response(204)
        self.end_headers()
        message = json.loads(body or b"{}")
        if message.get("done") or message.get("error"):
            if message.get("error"):
                reports.append(message)
            done.set()
        else:
            reports.append(message)

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


socketserver.TCPServer.allow_reuse_address = True
with socketserver.ThreadingTCPServer(("127.0.0.1", 0), Handler) as server:
    port = server.server_address[1]
    threading.Thread(target=server.serve_forever, daemon=True).start()
    profile = tempfile.mkdtemp(prefix="aograph-chromium-")
    url = f"http://127.0.0.1:{port}/index.html?test={','.join(techniques)}"
    started = time.time()
    browser = subprocess.Popen(chromium([url], profile), stdout=subprocess.DEVNULL,
                               stderr=open(os.path.join(profile, "stderr.log"), "w"))
    finished = done.wait(timeout=300)
    browser.kill()
    browser.wait()
    seconds = time.time() - started
    if SCREENSHOT:
        subprocess.run(chromium([f"--screenshot={os.path.abspath(SCREENSHOT)}",
                                 "--window-size=1340,600",
                                 f"http://127.0.0.1:{port}/index.html?present=copy&hold&scene=columns"], profile + "-shot"),
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=180)
    server.shutdown()

failures = []
if not finished:
    failures.append(f"the page did not finish within 300 s ({len(reports)} report(s) came)")
by_name = {r.get("technique"): r for r in reports}
for r in reports:
    if r.get("error"):
        failures.append(f"the page failed to start: {r['error']}")
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
    # Same frames and arithmetic on two devices (SwiftShader, lavapipe): the means agree to
    # well under 0.01 unless the page ran something else.
    if abs(mean - n["mean"]) > 0.01:
        failures.append(f"{t}: browser mean {mean:.4f} differs from native {n['mean']:.4f} by more than 0.01")
    # Open floor: nothing within R occludes it (AO 1 up to the output's 8-bit step).
    if at(floor) < 0.98:
        failures.append(f"{t}: open floor reads {at(floor):.3f}, expected about 1")
    # The crease is occluded by two walls: visibly darker than open floor.
    if at(crease) > 0.9:
        failures.append(f"{t}: the crease reads {at(crease):.3f}, expected it dark (<= 0.9)")
print(f"web_check: {len(techniques)} techniques in headless Chromium in {seconds:.0f} s")
if failures:
    print("web_check: FAILED\n  " + "\n  ".join(failures), file=sys.stderr)
    sys.exit(1)
print("web_check: passed")
