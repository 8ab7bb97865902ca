#!/usr/bin/env python3
"""The report page in a real browser (ctest report.browser): headless Chromium, driven through chromedriver's
W3C WebDriver HTTP protocol with the standard library alone, opens a report of a tiny run from disk and checks
that the page logs no console error, that the values under a synthetic cursor are the EXRs' (as half floats),
and that the exposure slider and flipping change the canvas. A screenshot is kept beside the report.

Usage: browser_check.py CLRADIOSITY_BINARY SCENE.xml OUT_DIR
Exit 77 (ctest: skipped) where no browser or driver is installed, or the Python module to read EXRs is missing."""
import base64
import json
import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.request

SKIP = 77


def skip(why):
    print("skipped: " + why)
    sys.exit(SKIP)


def find_browser():
    driver = shutil.which("chromedriver")
    browser = next((b for b in (shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome")) if b),
                   None)
    if not driver or not browser:
        skip("no headless Chromium here (apt-get install chromium chromium-driver; .ci/install-deps installs them)")
    return driver, browser


def run(cli, *args):
    r = subprocess.run([cli, *map(str, args)], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"clradiosity {' '.join(map(str, args))} failed ({r.returncode}): {r.stderr.strip()}")
    return r.stdout


class WebDriver:
    """The few W3C WebDriver commands the check needs, over HTTP to a chromedriver this process starts."""

    ELEMENT = "element-6066-11e4-a52e-4f735466cecf"

    def __init__(self, driver, browser):
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            self.port = s.getsockname()[1]
        self.process = subprocess.Popen([driver, f"--port={self.port}"], stdout=subprocess.DEVNULL,
                                        stderr=subprocess.DEVNULL)
        self.base = f"http://127.0.0.1:{self.port}"
        for _ in range(100):
            try:
                if self.request("GET", "/status")["ready"]:
                    break
            except OSError:
                time.sleep(0.1)
        caps = {"browserName": "chrome",
                "goog:loggingPrefs": {"browser": "ALL"},
                "goog:chromeOptions": {"binary": browser,
                                       "args": ["--headless=new", "--no-sandbox", "--disable-gpu",
                                                "--disable-dev-shm-usage", "--window-size=1400,1100",
                                                "--force-device-scale-factor=1"]}}
        self.session = self.request("POST", "/session", {"capabilities": {"alwaysMatch": caps}})["sessionId"]

    def request(self, method, path, body=None):
        data = None if body is None else json.dumps(body).encode()
        req = urllib.request.Request(self.base + path, data=data, method=method,
                                     headers={"Content-Type": "application/json"})
        try:
            with urllib.request.urlopen(req, timeout=60) as r:
                return json.loads(r.read())["value"]
        except urllib.error.HTTPError as e:
            raise RuntimeError(f"WebDriver {method} {path}: {e.read().decode()[:500]}") from None

    def command(self, method, path, body=None):
        return self.request(method, f"/session/{self.session}{path}", body)

    def script(self, source, *args):
        return self.command("POST", "/execute/sync", {"script": source, "args": list(args)})

    def element(self, css):
        found = self.command("POST", "/element", {"using": "css selector", "value": css})
        if self.ELEMENT not in found:
            raise RuntimeError(f"no element {css}: {found}")
        return found[self.ELEMENT]

    def move_to(self, element, dx, dy):
        # W3C pointer origin at an element: offsets from its centre, in CSS pixels.
        self.command("POST", "/actions", {"actions": [{
            "type": "pointer", "id": "mouse", "parameters": {"pointerType": "mouse"},
            "actions": [{"type": "pointerMove", "duration": 0, "origin": {self.ELEMENT: element},
                         "x": dx, "y": dy}]}]})

    def click(self):
        self.command("POST", "/actions", {"actions": [{
            "type": "pointer", "id": "mouse", "parameters": {"pointerType": "mouse"},
            "actions": [{"type": "pointerDown", "button": 0}, {"type": "pointerUp", "button": 0}]}]})

    def wheel(self, element, delta_y):
        self.command("POST", "/actions", {"actions": [{
            "type": "wheel", "id": "wheel",
            "actions": [{"type": "scroll", "x": 0, "y": 0, "deltaX": 0, "deltaY": delta_y,
                         "origin": {self.ELEMENT: element}}]}]})

    def key(self, k):
        self.command("POST", "/actions", {"actions": [{
            "type": "key", "id": "keyboard", "actions": [{"type": "keyDown", "value": k},
                                                         {"type": "keyUp", "value": k}]}]})

    def console(self):
        # chromedriver's log endpoint (outside W3C, kept by chromedriver for this purpose).
        return self.command("POST", "/se/log", {"type": "browser"})

    def close(self):
        try:
            self.command("DELETE", "")
        finally:
            self.process.terminate()
            self.process.wait(10)


def main():
    cli, scene, out = sys.argv[1], sys.argv[2], sys.argv[3]
    driver, browser = find_browser()
    try:
        import clradiosity  # the build tree's module (PYTHONPATH), to read the EXRs independently of the page
    except ImportError as e:
        skip(f"the clradiosity Python module is not importable ({e})")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    ref, run_dir, model = f"{out}/ref.exr", f"{out}/run", f"{out}/model.exr"
    config = f"{out}/small.json"
    with open(config, "w") as f:
        json.dump({"batch": 256, "log_every": 5, "network": {
            "width": 32, "hidden_layers": 2, "encoder": {"grid": {"levels": 4, "log2_table": 12}}}}, f)
    t = time.time()
    run(cli, "reference", scene, "--spp", 4, "--width", 32, "--height", 32, "-o", ref)
    run(cli, "train", scene, "--method", "isnr", "--steps", 10, "--config", config, "--reference", ref,
        "--eval-every", 5, "--eval-spp", 1, "-o", run_dir)
    run(cli, "render", scene, "--model", run_dir, "--width", 32, "--height", 32, "--spp", 1, "-o", model)
    page = f"{out}/report.html"
    run(cli, "report", run_dir, "--reference", ref, "--model-image", model, "--path-tracer-max-spp", 2,
        "--guide-grid", 2, "--guide-resolution", 16, "-o", page)
    print(f"report made in {time.time() - t:.1f} s")

    wd = WebDriver(driver, browser)
    try:
        t = time.time()
        wd.command("POST", "/url", {"url": "file://" + os.path.abspath(page)})
        # The images are inflated asynchronously: the page says when it is built.
        ready = False
        while not ready and time.time() - t < 30:
            ready = wd.script("return document.body.dataset.ready === '1' && !!clrReport.viewer")
            if not ready:
                time.sleep(0.05)
        print(f"page opened in {time.time() - t:.2f} s")
        assert ready, f"the page's script did not finish: {wd.console()}"

        # The values under a synthetic cursor: pixel (20, 9) of the 32×32 images, drawn 12× (the base scale).
        scale = wd.script("return clrReport.viewer.baseScale")
        canvas = wd.element("canvas[data-key=model]")
        size = wd.script("const r = arguments[0].getBoundingClientRect(); return [r.width, r.height]",
                         {WebDriver.ELEMENT: canvas})
        x, y = 20, 9
        wd.move_to(canvas, int((x + 0.5) * scale - size[0] / 2), int((y + 0.5) * scale - size[1] / 2))
        at = wd.script("const d = document.getElementById('readout').dataset;"
                       "return [Number(d.x), Number(d.y), JSON.parse(d.values || 'null')]")
        assert at[0] == x and at[1] == y, f"cursor read pixel {at[:2]}, wanted {(x, y)}"
        for key, file in (("model", model), ("reference", ref)):
            exr = clradiosity.read_image(file)
            want = [float(v) for v in exr[y, x, :3]]
            got = at[2][key]
            for g, w in zip(got, want):
                assert abs(g - w) <= 1e-3 * abs(w) + 1e-6, f"{key} at {(x, y)}: page {got}, EXR {want}"
        print(f"pixel {(x, y)}: page {at[2]['model']} = EXR (model), {at[2]['reference']} (reference)")

        # Exposure changes what the canvas shows.
        before = wd.script("return arguments[0].toDataURL()", {WebDriver.ELEMENT: canvas})
        wd.script("const e = document.getElementById('exposure'); e.value = 2; e.dispatchEvent(new Event('input'))")
        after = wd.script("return arguments[0].toDataURL()", {WebDriver.ELEMENT: canvas})
        assert before != after, "the exposure slider did not change the canvas"

        # Flipping with the key shows another image in place.
        visible = "return [...document.querySelectorAll('.panel:not(.hidden)')].map(p => p.dataset.key)"
        wd.key("1")
        first = wd.script(visible)
        wd.key("f")
        second = wd.script(visible)
        assert first == ["model"] and len(second) == 1 and second != first, f"flip showed {first} then {second}"
        shown = lambda k: wd.script("return document.querySelector(`canvas[data-key=${arguments[0]}]`).toDataURL()", k)
        assert shown(first[0]) != shown(second[0]), "flipping showed the same picture"
        wd.key("m")  # back to side by side for the screenshot
        assert len(wd.script(visible)) > 2

        # The guide: a click shows the lobes at the precomputed pixel nearest to it (a 2 x 2 grid: 8 and 24).
        canvas = wd.element("canvas[data-key=model]")
        wd.move_to(canvas, int((22 + 0.5) * scale - size[0] / 2), int((25 + 0.5) * scale - size[1] / 2))
        wd.click()
        guide = wd.script("const d = document.getElementById('guide-info').dataset; return [Number(d.x), Number(d.y),"
                          " document.querySelectorAll('#guide-maps canvas').length]")
        assert guide == [24, 24, 2], f"the guide after a click at (22, 25): {guide}"

        # Zoom is one for every canvas: the wheel over the model zooms the reference in step.
        pictures = "return [...document.querySelectorAll('.panel canvas')].map(c => c.toDataURL())"
        before = wd.script(pictures)
        wd.wheel(wd.element("canvas[data-key=model]"), -300)
        after = wd.script(pictures)
        zoom = wd.script("return clrReport.viewer.zoom")
        assert zoom > 1 and all(a != b for a, b in zip(before, after)), f"zoom {zoom}: not every canvas changed"
        wd.key("r")

        errors = [e for e in wd.console() if e.get("level") == "SEVERE"]
        assert not errors, f"console errors: {errors}"
        charts = wd.script("return document.querySelectorAll('#charts svg').length")
        assert charts > 0, "no convergence chart"
        with open(f"{out}/report.png", "wb") as f:
            f.write(base64.b64decode(wd.command("GET", "/screenshot")))
        print(f"screenshot: {out}/report.png; {charts} charts; no console errors")
    finally:
        wd.close()


if __name__ == "__main__":
    main()
