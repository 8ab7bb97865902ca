"""The Python module against the command line it wraps (docs/python.md).

Run by ctest (python.pytest: the build tree's module; python.pip_install: the module `pip install .` built), with
CLR_CLI naming the clradiosity binary of the same checkout: where the module and the CLI do the same thing, their
images and figures must be equal, bit for bit — the module is the CLI's code, not a second implementation."""

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import clradiosity as cr

SOURCE = Path(__file__).resolve().parents[2]
BOX = SOURCE / "scenes" / "cornell-box.xml"
FURNACE = SOURCE / "scenes" / "furnace-enclosure.xml"
CLI = os.environ.get("CLR_CLI", "")
# Small enough for a few seconds of PoCL, with every part of the encoder (tests/support/small_training.hpp).
SMALL = {"batch": 512, "log_every": 5, "network": {"width": 64, "hidden_layers": 2,
                                                   "encoder": {"grid": {"levels": 4, "log2_table": 12,
                                                                        "base_resolution": 4}}}}


def cli(*args):
    if not CLI:
        pytest.skip("CLR_CLI names no clradiosity binary")
    r = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    return r


@pytest.fixture(scope="module")
def box():
    return cr.load_scene(BOX, res=32)


@pytest.fixture(scope="module")
def trained(box, tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "box"
    reports = []
    run = cr.train(box, out, steps=20, method="nr", config=SMALL, callback=reports.append)
    return run, reports


def test_devices_lists_one_default():
    devices = cr.devices()
    assert devices and sum(d["default"] for d in devices) == 1
    assert {"index", "platform", "name", "type", "compute_units"} <= set(devices[0])
    assert cr.devices(devices[0]["index"])[0]["name"] == devices[0]["name"]


def test_bad_input_is_value_error_with_the_cli_line(tmp_path):
    with pytest.raises(ValueError, match="no-such-device"):
        cr.devices("no-such-device")
    missing = tmp_path / "missing.xml"
    with pytest.raises(ValueError) as e:
        cr.load_scene(missing)
    assert str(missing) in str(e.value) and "\n" not in str(e.value)
    if CLI:
        r = cli("reference", missing, "--spp", 1, "-o", tmp_path / "x.exr")
        assert r.returncode == 2
        assert r.stderr.strip() == "clradiosity: error: " + str(e.value)
    bad = tmp_path / "bad.xml"
    bad.write_text("<scene version='3.0.0'><shape type='teapot'/></scene>")
    with pytest.raises(ValueError, match="teapot"):
        cr.load_scene(bad)


def test_scene_parameters_fill_the_defaults():
    assert cr.load_scene(BOX).film == (128, 128)
    small = cr.load_scene(BOX, res=16)
    assert small.film == (16, 16)
    assert small.parameters == {"res": "16"}
    assert small.digest != cr.load_scene(BOX).digest  # -D is part of the scene's identity
    assert small.files[0] == str(BOX)


def test_training_reports_every_step_and_writes_a_run(trained):
    run, reports = trained
    assert [r["step"] for r in reports] == list(range(1, 21))
    assert all(np.isfinite(r["loss"]) and r["seconds"] > 0 for r in reports)
    assert run.steps == 20
    assert run.config["method"] == "nr" and run.config["batch"] == 512
    assert run.log[-1]["step"] == 20


def test_render_is_the_cli_render_bit_for_bit(trained, box, tmp_path):
    run, _ = trained
    image = run.render(spp=2, seed=3)
    assert image.shape == (32, 32, 3) and image.dtype == np.float32
    assert np.isfinite(image).all() and image.mean() > 0
    wide = run.render(width=48, height=16, spp=1)
    assert wide.shape == (16, 48, 3)
    r = cli("render", BOX, "-D", "res=32", "--model", run.dir, "--spp", 2, "--seed", 3, "-o", tmp_path / "r.exr")
    assert r.returncode == 0, r.stderr
    assert np.array_equal(cr.read_image(tmp_path / "r.exr"), image)
    view = [0, 1, 6.8, 0, 1, 0, 0, 1, 0, 30]
    other = run.render(spp=2, seed=3, camera=view)
    r = cli("render", BOX, "-D", "res=32", "--model", run.dir, "--spp", 2, "--seed", 3, "--camera",
            ",".join(map(str, view)), "-o", tmp_path / "v.exr")
    assert r.returncode == 0, r.stderr
    assert np.array_equal(cr.read_image(tmp_path / "v.exr"), other)
    assert not np.array_equal(other, image)
    rhs = run.render(spp=2, seed=3, mode="rhs")
    r = cli("render", BOX, "-D", "res=32", "--model", run.dir, "--spp", 2, "--seed", 3, "--mode", "rhs", "-o",
            tmp_path / "rhs.exr")
    assert r.returncode == 0, r.stderr
    assert np.array_equal(cr.read_image(tmp_path / "rhs.exr"), rhs)
    assert not np.array_equal(rhs, image)


def test_render_refuses_another_scene_and_bad_views(trained):
    run, _ = trained
    with pytest.raises(ValueError, match="scene"):
        run.render(scene=cr.load_scene(FURNACE))
    with pytest.raises(ValueError, match="camera"):
        run.render(camera=[0, 0, 0, 0, 0, 0, 0, 1, 0, 30])
    with pytest.raises(ValueError, match="camera"):
        run.render(camera=[1, 2, 3])
    with pytest.raises(ValueError, match="mode"):
        run.render(mode="both")


def test_load_run_finds_its_scene(trained):
    run, _ = trained
    again = cr.load_run(run.dir)
    assert again.scene.digest == run.scene.digest
    assert np.array_equal(again.render(spp=1), run.render(spp=1))
    with pytest.raises(ValueError, match="model.clr"):
        cr.load_run(Path(run.dir) / "nothing-here")


def test_reference_is_the_cli_reference_and_compare_the_cli_compare(box, tmp_path):
    image = cr.reference(box, spp=4, width=16, height=16, seed=5)
    assert image.shape == (16, 16, 3) and np.isfinite(image).all() and image.max() > 0
    assert np.array_equal(image, cr.reference(box, spp=4, width=16, height=16, seed=5))
    r = cli("reference", BOX, "-D", "res=32", "--spp", 4, "--width", 16, "--height", 16, "--seed", 5, "-o",
            tmp_path / "ref.exr")
    assert r.returncode == 0, r.stderr
    assert np.array_equal(cr.read_image(tmp_path / "ref.exr"), image)

    better = cr.reference(box, spp=64, width=16, height=16, seed=6)
    metrics = cr.compare(image, better)
    # The definitions of docs/design.md §4, in numpy (in double precision, as the engine sums them).
    a, b = image.astype(np.float64), better.astype(np.float64)
    assert metrics["mape"] == pytest.approx(np.mean(np.abs(a - b) / (np.abs(b) + 0.01)), rel=1e-9)
    assert metrics["mse"] == pytest.approx(np.mean((a - b) ** 2), rel=1e-9)
    assert metrics["relmse"] == pytest.approx(np.mean((a - b) ** 2 / (b ** 2 + 0.01)), rel=1e-9)
    assert metrics["mean_ratio"] == pytest.approx(np.sum(a) / np.sum(b), rel=1e-9)
    cr_compare = cli("compare", tmp_path / "ref.exr", _write(tmp_path, better, box), "--json")
    assert cr_compare.returncode == 0, cr_compare.stderr
    assert json.loads(cr_compare.stdout)["mape"] == metrics["mape"]
    # A reference twice the size is box-downsampled, as `compare` does; other sizes are refused.
    assert cr.compare(image, np.repeat(np.repeat(better, 2, 0), 2, 1))["mape"] == pytest.approx(metrics["mape"])
    with pytest.raises(ValueError):
        cr.compare(image, better[:15])
    with pytest.raises(ValueError, match="float32"):
        cr.compare(image[..., :2], better)


def _write(tmp_path, image, box):
    # An EXR of `image` for the CLI: the reference of the same pixels, re-rendered by the CLI (its seed and spp).
    path = tmp_path / "better.exr"
    r = cli("reference", BOX, "-D", "res=32", "--spp", 64, "--width", 16, "--height", 16, "--seed", 6, "-o", path)
    assert r.returncode == 0, r.stderr
    assert np.array_equal(cr.read_image(path), image)
    return path


def test_a_scene_sensor_is_chosen_by_index(tmp_path):
    scene = tmp_path / "two.xml"
    text = BOX.read_text()
    end = text.index("</sensor>") + len("</sensor>")
    scene.write_text(text[:end] + '<sensor type="perspective"><float name="fov" value="40"/>'
                     '<transform name="to_world"><lookat origin="0.5, 1.5, 4" target="0, 0.8, 0" up="0, 1, 0"/>'
                     '</transform><sampler type="independent"><integer name="sample_count" value="2"/></sampler>'
                     '<film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/>'
                     '</film></sensor>' + text[end:])
    first, second = cr.load_scene(scene, res=32), cr.load_scene(scene, sensor=1, res=32)
    assert (first.film, second.film, second.sensor_count, second.sensor) == ((32, 32), (24, 16), 2, 1)
    assert first.digest == second.digest  # the same scene, another view
    assert cr.reference(second).shape == (16, 24, 3)  # its own sampler's 2 spp
    with pytest.raises(ValueError, match="has 2 sensors"):
        cr.load_scene(scene, sensor=2)


def test_a_loaded_scene_trains_as_loaded_after_chdir_or_edit(tmp_path, monkeypatch):
    # A scene loaded by a relative path, then the folder changed and the file edited: train() trains the scene the
    # Scene object holds, and the run records it by its absolute path.
    folder = tmp_path / "scene"
    folder.mkdir()
    (folder / "box.xml").write_text(BOX.read_text())
    for mesh in BOX.parent.iterdir():
        if mesh.is_dir():
            (folder / mesh.name).symlink_to(mesh)
    monkeypatch.chdir(folder)
    scene = cr.load_scene("box.xml", res=16)
    assert Path(scene.path).is_absolute() and Path(scene.path) == folder / "box.xml"
    monkeypatch.chdir(tmp_path)
    (folder / "box.xml").write_text(BOX.read_text().replace("</scene>", "<!-- edited -->\n</scene>"))
    run = cr.train(scene, tmp_path / "run", steps=2, config=SMALL, method="nr")
    record = json.loads((tmp_path / "run" / "scene.json").read_text())
    assert record["scene"] == str(folder / "box.xml")
    assert record["digest"] == scene.digest, "the run is of the scene as loaded, not of the edited file"
    assert run.steps == 2


def test_load_run_names_what_is_wrong_with_an_odd_folder(box, tmp_path):
    run = cr.train(box, tmp_path / "run", steps=2, method="nr", config=SMALL)
    record = (tmp_path / "run" / "scene.json").read_text()
    for text, why in [("[]", "no 'scene' path"), ('{"scene": 5}', "no 'scene' path"),
                      ('{"scene": "x.xml", "parameters": [1]}', "'parameters' is not an object"),
                      ("{", "scene.json")]:
        (tmp_path / "run" / "scene.json").write_text(text)
        with pytest.raises(ValueError, match=why):
            cr.load_run(tmp_path / "run")
    (tmp_path / "run" / "scene.json").write_text(record)
    log = (tmp_path / "run" / "log.csv").read_text()
    for text, why in [(log + "3,4\n", r"log\.csv:\d+: the row has fewer cells"),
                      (log.replace("\n2,", "\nx,", 1), r"log\.csv:\d+: step is not a number"),
                      ("seconds\n1\n", "no step")]:
        (tmp_path / "run" / "log.csv").write_text(text)
        with pytest.raises(ValueError, match=why):
            cr.load_run(tmp_path / "run").steps
    assert run.scene.digest == box.digest


def test_a_cli_run_with_any_parameter_name_loads(tmp_path):
    # -D path=… and -D sensor=… are scene parameters like any other: load_run passes them as such.
    xml = BOX.read_text().replace('<default name="res"', '<default name="path" value="16"/><default name="res"', 1)
    xml = xml.replace('value="$res"', 'value="$path"', 1)
    assert "$path" in xml
    (tmp_path / "box.xml").write_text(xml)
    r = cli("train", tmp_path / "box.xml", "--steps", "2", "--method", "nr", "--batch", "256", "-D", "path=24",
            "-o", tmp_path / "run")
    assert r.returncode == 0, r.stderr
    run = cr.load_run(tmp_path / "run")
    assert run.scene.parameters == {"path": "24"} and run.steps == 2


def test_reference_takes_the_scene_sampler_or_names_it(tmp_path):
    with pytest.raises(ValueError, match="sample_count"):
        cr.reference(cr.load_scene(BOX, res=8))
    scene = tmp_path / "sampled.xml"
    text = BOX.read_text().replace('<film type="hdrfilm">',
                                   '<sampler type="independent"><integer name="sample_count" value="3"/>'
                                   '</sampler><film type="hdrfilm">')
    scene.write_text(text.replace('href="meshes', 'href="%s/meshes' % (SOURCE / "scenes")))
    sampled = cr.load_scene(scene, res=8)
    assert sampled.sample_count == 3
    assert np.array_equal(cr.reference(sampled), cr.reference(sampled, spp=3))


def test_callback_false_stops_with_a_checkpoint_and_resume_continues(box, tmp_path):
    out = tmp_path / "stopped"
    run = cr.train(box, out, steps=50, method="nr", config=SMALL, callback=lambda r: r["step"] < 7)
    assert run.steps == 7
    cr.train(box, out, steps=12, resume=True)
    assert cr.load_run(out).steps == 12
    with pytest.raises(ValueError, match="--method"):
        cr.train(box, out, steps=15, method="isnr", resume=True)


def test_callback_exception_propagates_after_the_checkpoint(box, tmp_path):
    def fail(report):
        if report["step"] == 4:
            raise ArithmeticError("from the callback")

    with pytest.raises(ArithmeticError, match="from the callback"):
        cr.train(box, tmp_path / "failed", steps=50, method="nr", config=SMALL, callback=fail)
    assert cr.load_run(tmp_path / "failed").steps == 4


def test_settings_are_checked_as_the_cli_checks_them(box, tmp_path):
    with pytest.raises(ValueError, match="method"):
        cr.train(box, tmp_path / "a", steps=5, method="bogus")
    with pytest.raises(ValueError, match="budget"):
        cr.train(box, tmp_path / "b")
    with pytest.raises(ValueError, match="no_such_key"):
        cr.train(box, tmp_path / "c", steps=5, config={"no_such_key": 1})
    with pytest.raises(TypeError, match="bogus_setting"):
        cr.train(box, tmp_path / "d", steps=5, bogus_setting=3)
    assert not (tmp_path / "a").exists() and not (tmp_path / "c").exists()


def test_every_setting_is_judged_once_whatever_its_python_type(box, tmp_path):
    # The CLI's ranges, through the same checks: intervals below 1 and an evaluation spp past the CLI's limit are
    # refused, not taken for "the default"; NaN is refused by the setting's name, not by a JSON parser; numpy's
    # integers are integers and floats are not counts.
    reference = tmp_path / "ref.exr"
    cr.write_image(reference, np.ones((32, 32, 3), np.float32))
    refused = [(dict(reference=reference, eval_every=0), "--eval-every"),
               (dict(reference=reference, eval_every=-5), "--eval-every"),
               (dict(reference=reference, eval_spp=70000), "--eval-spp"),
               (dict(reference=reference, eval_every=2.5), "eval_every must be an integer"),
               (dict(preview=tmp_path / "p.png", preview_every=0), "--preview-every"),
               (dict(learning_rate=float("nan")), "learning_rate must be a finite number"),
               (dict(config={"network": {"adam": {"epsilon": float("inf")}}}), "config.network.adam.epsilon"),
               (dict(config={"network": {"outputs": 16}}), "network.outputs must be 3")]
    for i, (kwargs, why) in enumerate(refused):
        with pytest.raises(ValueError, match=why.replace(".", r"\.").replace("[", r"\[")):
            cr.train(box, tmp_path / f"r{i}", steps=4, method="nr", **{"config": SMALL, **kwargs})
        assert not (tmp_path / f"r{i}" / "model.clr").exists()
    with pytest.raises(ValueError, match="steps must be an integer"):
        cr.train(box, tmp_path / "float", steps=4.5, method="nr", config=SMALL)
    run = cr.train(box, tmp_path / "numpy", steps=np.int64(4), samples=np.int32(2), learning_rate=np.float32(0.004),
                   method="nr", config=SMALL, reference=reference, eval_every=np.int64(2), eval_spp=np.int16(1))
    assert (run.steps, run.config["samples"]) == (4, 2)


def test_isnr_with_settings_by_keyword(box, tmp_path):
    run = cr.train(box, tmp_path / "isnr", steps=6, config=SMALL, is_loss="kl", samples=2, bsdf_fraction=0.25,
                   learning_rate=0.002, seed=9)
    c = run.config
    assert (c["method"], c["is_loss"], c["samples"], c["bsdf_fraction"], c["seed"]) == ("isnr", "kl", 2, 0.25, 9)
    assert c["network"]["adam"]["learning_rate"] == pytest.approx(0.002)
    assert run.steps == 6


def test_long_calls_release_the_gil(box):
    done = threading.Event()
    ticks = 0

    def work():
        cr.reference(box, spp=96, width=32, height=32)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    assert ticks > 20  # the main thread ran while the path tracer did


def test_ctrl_c_checkpoints_then_raises_keyboard_interrupt(tmp_path):
    script = tmp_path / "long.py"
    out = tmp_path / "interrupted"
    script.write_text(
        "import sys, clradiosity as cr\n"
        "def report(r):\n"
        "    if r['step'] == 3: print('training', flush=True)\n"
        "try:\n"
        "    cr.train(cr.load_scene(%r, res=32), %r, minutes=5, method='nr', config=%r, callback=report)\n"
        "except KeyboardInterrupt:\n"
        "    print('KeyboardInterrupt', flush=True)\n"
        "    sys.exit(7)\n" % (str(BOX), str(out), SMALL))
    p = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
    assert p.stdout.readline().strip() == "training", p.stderr.read()
    p.send_signal(signal.SIGINT)
    stdout, stderr = p.communicate(timeout=60)
    assert p.returncode == 7, stderr
    assert "KeyboardInterrupt" in stdout
    assert cr.load_run(out).steps >= 3


def test_ctrl_c_stops_a_render_within_moments(box, tmp_path):
    # A render of minutes, interrupted: KeyboardInterrupt within about a second, as the CLI stops, not once the
    # whole image is done.
    run = cr.train(box, tmp_path / "run", steps=2, method="nr", config=SMALL)
    script = tmp_path / "render.py"
    script.write_text(
        "import sys, time, clradiosity as cr\n"
        "run = cr.load_run(%r)\n"
        "print('rendering', flush=True)\n"
        "start = time.monotonic()\n"
        "try:\n"
        "    run.render(width=1024, height=1024, spp=512)\n"
        "except KeyboardInterrupt:\n"
        "    print('KeyboardInterrupt %%.2f' %% (time.monotonic() - start), flush=True)\n"
        "    sys.exit(7)\n" % str(run.dir))
    p = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
    assert p.stdout.readline().strip() == "rendering", p.stderr.read()
    time.sleep(2)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    stdout, stderr = p.communicate(timeout=60)
    assert p.returncode == 7, stderr
    assert time.monotonic() - sent < 5, "the render ran on after Ctrl-C"


def test_two_threads_whose_first_call_trains_start_opencl_safely(tmp_path):
    # Cold starts in fresh processes: two threads enter the OpenCL start-up at once (the ICD loader's and PoCL's
    # first-use initialisation); every one must train, none crash or find no platform.
    script = tmp_path / "threads.py"
    script.write_text(
        "import sys, threading, clradiosity as cr\n"
        "scene = cr.load_scene(%r, res=16)\n"
        "errors = []\n"
        "def work(k):\n"
        "    try:\n"
        "        cr.train(scene, sys.argv[1] + '/run%%d' %% k, steps=1, method='nr', config=%r)\n"
        "    except Exception as e:\n"
        "        errors.append(repr(e))\n"
        "threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]\n"
        "[t.start() for t in threads]\n"
        "[t.join() for t in threads]\n"
        "print('errors', errors, flush=True)\n"
        "sys.exit(1 if errors else 0)\n" % (str(BOX), SMALL))
    for attempt in range(4):
        out = tmp_path / str(attempt)
        out.mkdir()
        r = subprocess.run([sys.executable, str(script), str(out)], capture_output=True, text=True, timeout=300,
                           env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
        assert r.returncode == 0, (attempt, r.returncode, r.stdout, r.stderr[-2000:])


def _interrupted_training(tmp_path, prelude, steps):
    """A script that sets up its SIGINT disposition (`prelude`), trains `steps` steps and prints how many it ran;
    SIGINT is sent once training has logged step 3. Returns the finished process and its stdout."""
    script = tmp_path / "signals.py"
    out = tmp_path / "run"
    script.write_text(
        "import signal, sys, clradiosity as cr\n" + prelude +
        "def report(r):\n"
        "    if r['step'] == 3: print('training', flush=True)\n"
        "run = cr.train(cr.load_scene(%r, res=32), %r, steps=%d, method='nr', config=%r, callback=report)\n"
        "print('steps', run.steps, flush=True)\n" % (str(BOX), str(out), steps, SMALL))
    p = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
    assert p.stdout.readline().strip() == "training", p.stderr.read()
    p.send_signal(signal.SIGINT)
    stdout, stderr = p.communicate(timeout=120)
    return p, stdout, stderr


def test_ctrl_c_that_python_ignores_does_not_stop_the_work(tmp_path):
    p, stdout, stderr = _interrupted_training(tmp_path, "signal.signal(signal.SIGINT, signal.SIG_IGN)\n", 60)
    assert p.returncode == 0, stderr
    assert "steps 60" in stdout


def test_ctrl_c_reaches_the_programs_own_handler_after_the_stop(tmp_path):
    prelude = ("def mine(sig, frame):\n"
               "    print('handled', flush=True)\n"
               "signal.signal(signal.SIGINT, mine)\n")
    p, stdout, stderr = _interrupted_training(tmp_path, prelude, 100000)
    assert p.returncode == 0, stderr
    assert "handled" in stdout  # the program's handler ran, and raised nothing
    steps = int(stdout.split("steps")[-1])
    assert 0 < steps < 100000  # the work stopped at the signal, with its checkpoint


def test_write_image_round_trips_and_refuses_other_extensions(tmp_path):
    image = np.random.default_rng(1).random((5, 7, 3), dtype=np.float32)
    cr.write_image(tmp_path / "a.exr", image, spp=3)
    assert np.array_equal(cr.read_image(tmp_path / "a.exr"), image)
    header = (tmp_path / "a.exr").read_bytes()[:4096]
    assert b"spp" in header and b"software" in header
    cr.write_image(tmp_path / "a.png", image)
    assert (tmp_path / "a.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(ValueError, match="a.jpg"):
        cr.write_image(tmp_path / "a.jpg", image)
    assert not (tmp_path / "a.jpg").exists()


def test_a_stop_from_a_callback_in_another_thread_is_forgotten(box, tmp_path):
    steps = {}

    def work():
        steps["first"] = cr.train(box, tmp_path / "t1", steps=20, method="nr", config=SMALL,
                                  callback=lambda r: r["step"] < 2).steps
        steps["second"] = cr.train(box, tmp_path / "t2", steps=5, method="nr", config=SMALL).steps

    t = threading.Thread(target=work)
    t.start()
    t.join()
    assert steps == {"first": 2, "second": 5}


def test_report_writes_the_page_the_cli_writes(trained, tmp_path):
    run, _ = trained
    ref = tmp_path / "ref.exr"
    cr.write_image(ref, cr.reference(cr.load_scene(BOX, res=32), spp=4, seed=7))
    page = tmp_path / "run.html"
    r = cr.report(run.dir, page, reference=ref, spp=1, path_tracer_max_spp=2)
    assert r["bytes"] == page.stat().st_size
    assert set(r["images"]) == {"model", "reference", "path_tracer"}
    assert r["images"]["path_tracer"]["notes"]["spp"] in ("1", "2")
    # The same metrics as the CLI's page of the same run (the model's render is deterministic).
    c = cli("report", run.dir, "--reference", ref, "--spp", 1, "--no-path-tracer", "-o", tmp_path / "cli.html")
    assert c.returncode == 0, c.stderr
    assert f"MAPE {r['images']['model']['mape']:.6g}" in c.stdout
    with pytest.raises(ValueError, match="must end in .html"):
        cr.report(run.dir, tmp_path / "run.png", reference=ref)
    with pytest.raises(ValueError, match="no such run folder"):
        cr.report(tmp_path / "none", page, reference=ref)
