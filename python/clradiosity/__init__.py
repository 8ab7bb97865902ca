"""clradiosity: Importance-Sampling-Guided Neural Radiosity on OpenCL devices, from Python.

A thin layer over the engine the ``clradiosity`` command runs (docs/python.md): the same scene loader, trainer,
renderers and metrics, with images as numpy arrays of shape (H, W, 3), float32, linear RGB.

    import clradiosity as cr
    scene = cr.load_scene("scenes/cornell-box.xml")
    run = cr.train(scene, steps=500, out="cbox-run")
    image = run.render(spp=16)
    reference = cr.reference(scene, spp=256)
    print(cr.compare(image, reference))   # {'mape': ..., 'mse': ..., 'relmse': ...}

Bad input raises ValueError with the command line's one-line message; other failures RuntimeError. Ctrl-C stops a
training at its next step with a checkpoint (``resume=True`` continues it) and then raises KeyboardInterrupt.
"""

import csv
import json
import math
import operator
import os
import warnings

import numpy as np

from . import _clradiosity as _native

__version__ = _native.__version__
__all__ = ["devices", "set_threads", "load_scene", "train", "load_run", "reference", "compare", "report", "read_image", "write_image",
           "Scene", "Run"]

Scene = _native.Scene


def _array(image):
    # The native image's buffer, copied into an array that owns its memory.
    return np.array(image, dtype=np.float32, copy=True)


def _camera(camera):
    if camera is None:
        return None
    values = [float(v) for v in camera]
    if len(values) != 10:
        raise ValueError("camera: give 10 numbers (origin, target, up, vertical fov in degrees), not %d" % len(values))
    return values


def devices(device=None):
    """The OpenCL devices as `clradiosity devices --json` lists them (a list of dicts; 'default' marks the one
    used when none is named). ``device``: a --device SPEC, to resolve it (ValueError when nothing matches)."""
    return json.loads(_native.devices_json(device or ""))


def set_threads(threads):
    """Caps the host's worker threads (and a PoCL CPU device's), as --threads; call it before the first device is
    used."""
    _native.set_threads(int(threads))


def set_quiet():
    """No progress lines on stderr from now on, as -q."""
    _native.set_quiet()


def load_scene(path, sensor=0, **parameters):
    """A Mitsuba scene; keyword arguments fill its $parameters, as ``-D key=value`` (values become strings).
    ``sensor``: which of its sensors, in the file's order, renders (as --sensor)."""
    return _native.Scene(os.fspath(path), {str(k): _parameter(v) for k, v in parameters.items()}, int(sensor))


def _parameter(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def _scene(scene):
    return scene if isinstance(scene, _native.Scene) else load_scene(scene)


# Keyword arguments of train(): the flags of `clradiosity train` that set a run's settings, by their names
# ("--is-loss" is is_loss), each with its path in config.json and the flag itself (a resumed run refuses a flag that
# contradicts its settings).
_SETTINGS = {flag[2:].replace("-", "_"): (tuple(pointer.strip("/").split("/")), flag)
             for flag, pointer in _native.setting_flags()}


def _integer(name, value):
    """An integer setting as given: Python's and numpy's integers, not floats (2.5 steps is not a count)."""
    if isinstance(value, bool):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    try:
        return operator.index(value)
    except TypeError:
        raise ValueError(f"{name} must be an integer, got {value!r}") from None


def _plain(name, value):
    """A setting as JSON takes it: numpy scalars as Python numbers; NaN and infinities refused by name (JSON has
    none, and they are no setting's value)."""
    if isinstance(value, dict):
        return {k: _plain(f"{name}.{k}", v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(f"{name}[{i}]", v) for i, v in enumerate(value)]
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):
        value = value.item()  # numpy scalars (and 0-d arrays)
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {value}")
    return value


def train(scene, out, *, steps=None, minutes=None, method=None, config=None, preset=None, device=None, resume=False,
          reference=None, eval_every=None, eval_spp=None, eval_mode=None, preview=None, preview_every=None, callback=None,
          **settings):
    """Trains a model of ``scene`` (a Scene or a path) into the run directory ``out``, as `clradiosity train`, and
    returns its Run.

    Budget: ``steps`` or ``minutes`` (or a ``preset``: preview, balanced, quality, paper). ``method``: "isnr"
    (default) or "nr". ``config``: a dict of settings or a JSON file, as --config. More settings by keyword, as the
    flags: is_loss, residual, nee (True/False), samples, batch, seed, bsdf_fraction, learning_rate, guide_learning_rate,
    gemm.
    ``reference`` (an EXR path) logs MAPE/MSE/relMSE in log.csv every ``eval_every`` steps, as --reference, of
    images at ``eval_spp`` in ``eval_mode`` ("lhs" or "rhs", as Run.render's ``mode``).
    ``callback(report)`` is called after every step with {'step', 'loss', 'seconds'}; returning False ends the run
    there, with its checkpoint.
    """
    given = dict(settings, steps=steps, minutes=minutes, method=method)
    unknown = sorted(set(settings) - set(_SETTINGS))
    if unknown:
        raise TypeError("train() got unexpected keyword arguments: " + ", ".join(unknown))
    given = {k: _plain(k, v) for k, v in given.items() if v is not None}
    if "steps" in given:
        given["steps"] = _integer("steps", given["steps"])

    def apply(patch):
        for key, value in given.items():
            path, _ = _SETTINGS[key]
            target = patch
            for part in path[:-1]:
                target = target.setdefault(part, {})
            target[path[-1]] = value

    config_file, config_json = "", ""
    if isinstance(config, dict):
        config_json = json.dumps(_plain("config", config), allow_nan=False)
    elif config is not None:
        config_file = os.fspath(config)

    def report(step):
        result = callback(step)
        return result is None or bool(result)

    scene = _scene(scene)
    flags = [flag for key, (_, flag) in _SETTINGS.items() if key in given]
    if eval_every is not None:
        flags.append("--eval-every")
    if eval_spp is not None:
        flags.append("--eval-spp")
    if eval_mode is not None:
        flags.append("--eval-mode")
    if preview_every is not None:
        flags.append("--preview-every")
    outcome = _native.train(scene, os.fspath(out), device or "", preset or "", config_file, config_json,
                            bool(resume), apply, flags, os.fspath(reference) if reference is not None else "",
                            _integer("eval_every", eval_every) if eval_every is not None else 0,
                            _integer("eval_spp", eval_spp) if eval_spp is not None else 0, str(eval_mode or ""),
                            os.fspath(preview) if preview is not None else "",
                            _integer("preview_every", preview_every) if preview_every is not None else 0,
                            report if callback is not None else None)
    if outcome["side_output_failures"]:
        # Each was reported on stderr as it happened; the model and its checkpoint are whole.
        warnings.warn(f"train: {outcome['side_output_failures']} preview, evaluation or figure write(s) failed "
                      f"(reported above); the training and its checkpoint are complete", RuntimeWarning, stacklevel=2)
    return Run(out, scene=scene, device=device)


def load_run(run_dir, scene=None, device=None):
    """A run directory written by train() or `clradiosity train`. ``scene`` defaults to the one the run records
    (its path as given when it was trained, with its parameters)."""
    return Run(run_dir, scene=scene, device=device)


class Run:
    """A run directory: its settings, its log and its model, which render() renders."""

    def __init__(self, run_dir, scene=None, device=None):
        self.dir = os.fspath(run_dir)
        if not os.path.isfile(os.path.join(self.dir, "model.clr")):
            raise ValueError("%s: no model.clr (not a run directory, or its training wrote no checkpoint)" % self.dir)
        if scene is None:
            record = self._json("scene.json")
            where = os.path.join(self.dir, "scene.json")
            if not isinstance(record, dict) or not isinstance(record.get("scene"), str):
                raise ValueError("%s: not a run's scene record (no 'scene' path)" % where)
            parameters = record.get("parameters", {})
            if not isinstance(parameters, dict) or not all(isinstance(v, str) for v in parameters.values()):
                raise ValueError("%s: 'parameters' is not an object of strings" % where)
            # The parameters as a mapping, not as keywords: `-D path=…` or `-D sensor=…` are scene parameters too.
            scene = _native.Scene(record["scene"], dict(parameters), 0)
        self.scene = _scene(scene)
        self._device = device or ""
        self._model = None

    def _json(self, name):
        path = os.path.join(self.dir, name)
        try:
            with open(path) as f:
                return json.load(f)
        except (OSError, ValueError) as e:
            raise ValueError("%s: %s" % (path, e)) from None

    @property
    def config(self):
        """The run's settings (config.json)."""
        return self._json("config.json")

    @property
    def log(self):
        """log.csv's rows as dicts of floats (None where a column is empty, e.g. steps without an evaluation)."""
        path = os.path.join(self.dir, "log.csv")
        try:
            with open(path, newline="") as f:
                rows = list(csv.DictReader(f))
        except (OSError, csv.Error, UnicodeDecodeError) as e:
            raise ValueError("%s: %s" % (path, e)) from None

        def number(line, column, text):
            if text is None:
                raise ValueError("%s:%d: the row has fewer cells than the header" % (path, line))
            try:
                return float(text) if text != "" else None
            except ValueError:
                raise ValueError("%s:%d: %s is not a number: %r" % (path, line, column, text[:40])) from None

        out = []
        for line, row in enumerate(rows, start=2):
            if None in row:
                raise ValueError("%s:%d: the row has more cells than the header" % (path, line))
            out.append({k: number(line, k, v) for k, v in row.items()})
        return out

    @property
    def model(self):
        if self._model is None:
            self._model = _native.Model(os.path.join(self.dir, "model.clr"), self._device)
        return self._model

    @property
    def steps(self):
        """Steps trained so far (log.csv's last row)."""
        log = self.log
        if not log:
            return 0
        if log[-1].get("step") is None:
            raise ValueError("%s: its last row has no step" % os.path.join(self.dir, "log.csv"))
        return int(log[-1]["step"])

    def render(self, width=0, height=0, spp=4, seed=1, camera=None, scene=None, mode="lhs"):
        """The model's image (H, W, 3) float32, as `render`: ``mode`` "lhs", Le + L at the first non-delta hit of
        each camera ray, or "rhs", one more bounce there (the direct light and one BSDF sample, L where it lands).
        ``width``/``height``: 0 keeps the film's. ``camera``: 10 numbers (origin, target, up, vertical fov) for
        another view. ``scene``: another instance of the run's scene (e.g. loaded with other parameters)."""
        return _array(self.model.render(_scene(scene) if scene is not None else self.scene, int(width), int(height),
                                        int(spp), int(seed), _camera(camera), str(mode)))

    def __repr__(self):
        return "Run(%r)" % self.dir


def reference(scene, spp=None, width=0, height=0, max_depth=None, seed=0, camera=None):
    """A path-traced image (H, W, 3) float32 of ``scene`` (a Scene or a path), as `clradiosity reference`: ``spp``
    defaults to the scene's sampler, ``max_depth`` to its integrator's."""
    return _array(_native.reference(_scene(scene), int(spp or 0), int(width), int(height),
                                    None if max_depth is None else int(max_depth), int(seed), _camera(camera)))


def compare(image, reference):
    """MAPE, MSE and relMSE of ``image`` against ``reference`` (arrays (H, W, 3)), as `clradiosity compare`: a
    reference an integer multiple of the image's size is box-downsampled to it."""
    return _native.compare(np.ascontiguousarray(image, dtype=np.float32),
                           np.ascontiguousarray(reference, dtype=np.float32))


def report(run_dir, out, *, reference=None, scene=None, spp=0, path_tracer=True, path_tracer_seconds=0,
           path_tracer_max_spp=1024, guide_grid=6, guide_resolution=32, device=None):
    """Writes the run's report page ``out`` (.html), as `clradiosity report` does: the model's render, the reference
    and the path tracer at the run's training time compared in one self-contained page, with its convergence and
    record (an ISNR run's guide at guide_grid x guide_grid pixels). Images are rendered where not given; returns {"path", "bytes", "images": {key: {title, notes, mape, mse,
    relmse}}}."""
    return _native.report(os.fspath(run_dir), os.fspath(out), os.fspath(reference) if reference else "",
                          os.fspath(scene) if scene else "", _integer("spp", spp), bool(path_tracer),
                          float(path_tracer_seconds), _integer("path_tracer_max_spp", path_tracer_max_spp),
                          device or "", _integer("guide_grid", guide_grid),
                          _integer("guide_resolution", guide_resolution))


def read_image(path):
    """An EXR file as an (H, W, 3) float32 array."""
    return _array(_native.read_image(os.fspath(path)))


def write_image(path, image, **attributes):
    """Writes an (H, W, 3) array as the format its extension names: .exr (linear float; keyword arguments become
    string attributes of its header, beside software) or .png (sRGB, 8 bits), atomically."""
    attributes = {str(k): str(v) for k, v in attributes.items()}
    attributes.setdefault("software", "clradiosity " + __version__ + " (Python)")
    _native.write_image(os.fspath(path), np.ascontiguousarray(image, dtype=np.float32), attributes)
