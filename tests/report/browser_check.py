#!/usr/bin/env python3
"""The report page in a real browser (ctest report.browser): headless Chromium, driven through chromedriver's
W3C WebDriver HTTP protocol with the standard library alone, opens a report of a tiny run from disk and checks
that the page logs no console error, that the values under a synthetic cursor are the EXRs' (as half floats),
that the exposure slider and flipping change the canvas, and that the record names the run's commit and peak
memory. Then a paper-tables folder made of two tiny runs: its table of our rows beside the paper's sorts on a
click of a header, and hovering a row picks out that run's curves. A screenshot of each page is kept beside it.

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

        # The record: the run's own commit (sessions.json) and its peak memory, as the page shows them.
        record = wd.script("return Object.fromEntries([...document.querySelectorAll('#record-body tr')]"
                           ".map(r => [r.cells[0].textContent, r.cells[1].textContent]))")
        assert "(commit " in record.get("trained by", ""), f"record: trained by {record.get('trained by')}"
        for key in ("peak device memory", "peak resident memory"):
            assert record.get(key, "").endswith(" MiB"), f"record: {key} {record.get(key)}"
        print(f"record: trained by {record['trained by']}; peak device memory {record['peak device memory']}")

        errors = [e for e in wd.console() if e.get("level") == "SEVERE"]
        assert not errors, f"console errors: {errors}"
        charts = wd.script("return document.querySelectorAll('#charts svg').length")
        assert charts > 0, "no convergence chart"
        with open(f"{out}/report.png", "wb") as f:
            f.write(base64.b64decode(wd.command("GET", "/screenshot")))
        print(f"screenshot: {out}/report.png; {charts} charts; no console errors")

        check_paper_tables(wd, cli, scene, out, run_dir, ref, config)
    finally:
        wd.close()


def open_page(wd, page):
    t = time.time()
    wd.command("POST", "/url", {"url": "file://" + os.path.abspath(page)})
    while time.time() - t < 30:
        if wd.script("return document.body.dataset.ready === '1'"):
            return time.time() - t
        time.sleep(0.05)
    raise AssertionError(f"{page}: the page's script did not finish: {wd.console()}")


def check_paper_tables(wd, cli, scene, out, isnr_run, ref, config):
    """A paper-tables folder as bench/paper_tables.sh lays it out, recorded as the paper's Wooden Staircase: the
    tiny ISNR run and an NR one, with a path tracer's points."""
    folder = f"{out}/paper"
    runs = f"{folder}/runs/staircase"
    os.makedirs(runs)
    os.makedirs(f"{folder}/path_tracer/staircase")
    shutil.copytree(isnr_run, f"{runs}/t1-isnr-ikl")
    run(cli, "train", scene, "--method", "nr", "--steps", 10, "--config", config, "--reference", ref,
        "--eval-every", 5, "--eval-spp", 1, "-o", f"{runs}/t1-nr")
    with open(f"{runs}/scene.json", "w") as f:
        json.dump({"scene": scene, "paper_scene": "WoodenStaircase", "reference": ref, "width": 32, "height": 32,
                   "eval_spp": 1, "preset": ""}, f)
    with open(f"{folder}/path_tracer/staircase/points.csv", "w") as f:
        f.write("spp,seconds,mape,mse,relmse\n1,0.01,0.9,0.2,0.8\n2,0.02,0.6,0.1,0.5\n4,0.04,0.4,0.05,0.3\n")
    page = f"{folder}/report.html"
    run(cli, "report", folder, "-o", page)
    print(f"paper tables page opened in {open_page(wd, page):.2f} s")

    rows = "return [...document.querySelectorAll('table.paper-table tbody tr')].map(r => r.dataset.key)"
    assert sorted(wd.script(rows)) == ["t1-isnr-ikl", "t1-nr"], wd.script(rows)
    # The paper's numbers beside ours: Table 1's MAPE on Wooden Staircase (bench/paper/paper.json).
    cells = wd.script("const r = document.querySelector('table.paper-table tbody tr[data-key=\"t1-nr\"]');"
                      "const h = [...document.querySelectorAll('table.paper-table thead th')].map(t => t.dataset.key);"
                      "return Object.fromEntries(h.map((k, i) => [k, r.cells[i].textContent]))")
    assert cells["paper_mape"] == "0.0400" and cells["paper_step"] == "25000", f"t1-nr's paper cells: {cells}"
    # A click on a header sorts by it; a second click the other way.
    mape = wd.script("return clrReport.data.paper.scenes[0].runs.map(r => [r.label, r.final.mape])")
    ascending = [label for label, _ in sorted(mape, key=lambda m: m[1])]
    wd.script("document.querySelector('table.paper-table th[data-key=mape]').click()")
    assert wd.script(rows) == ascending, f"sorted by MAPE: {wd.script(rows)}, wanted {ascending}"
    wd.script("document.querySelector('table.paper-table th[data-key=mape]').click()")
    assert wd.script(rows) == ascending[::-1], f"sorted by MAPE, descending: {wd.script(rows)}"
    # Hovering a row picks out its run in every chart (the others dimmed); the paper's points are its own too.
    wd.move_to(wd.element("table.paper-table tbody tr[data-key=t1-nr]"), 0, 0)
    dimmed = wd.script("return [...document.querySelectorAll('#paper g.series')].map(g => [g.dataset.series,"
                       " g.classList.contains('dim')])")
    assert dimmed and all(d == (label != "t1-nr") for label, d in dimmed), f"hover on t1-nr: {dimmed}"
    hollow = wd.script("return document.querySelectorAll('#paper g.series[data-series=\"t1-nr\"] circle"
                       "[fill=none]').length")
    assert hollow >= 1, "no paper point beside t1-nr's curve"
    errors = [e for e in wd.console() if e.get("level") == "SEVERE"]
    assert not errors, f"console errors on the paper tables page: {errors}"
    with open(f"{out}/report-paper.png", "wb") as f:
        f.write(base64.b64decode(wd.command("GET", "/screenshot")))
    print(f"screenshot: {out}/report-paper.png; sorting and hovering work; no console errors")


if __name__ == "__main__":
    main()
