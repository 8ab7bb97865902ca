#!/usr/bin/env python3
"""Renders a scene with Mitsuba 3 (scalar_rgb), the independent peer of mitsuba_peer_slow_test.cpp.

Usage: mitsuba_render.py SCENE.xml WIDTH HEIGHT SPP MAX_DEPTH OUT.exr [SEED [COUNT]]

The scene file is used unchanged: Mitsuba's own `path` integrator (with MAX_DEPTH) replaces whatever the file names
(the shared scenes name integrators Mitsuba does not ship), and the camera is re-created at the requested size with
the loaded sensor's transform and horizontal field of view (a thin lens with its aperture and focus distance, an
orthographic camera with its transform). Exits 3 when Mitsuba cannot load the scene, so that a caller can tell
"Mitsuba has no opinion" from a failed render. With COUNT, renders seeds SEED … SEED + COUNT − 1 of the scene loaded
once (the peer tests' independent renders), each to OUT with "-SEED" before its extension."""
import os
import re
import sys
import xml.etree.ElementTree as ET

import mitsuba as mi

mi.set_variant("scalar_rgb")
scene_file, width, height, spp, max_depth, out = sys.argv[1:7]
seed = int(sys.argv[7]) if len(sys.argv) > 7 else 0
count = int(sys.argv[8]) if len(sys.argv) > 8 else None

def scalar(v):
    return float(v[0]) if hasattr(v, "__len__") else float(v)


def included_defaults(path):
    """The <default> values of the scene's included files: Mitsuba takes defaults from the main file only,
    clradiosity (like Mitsuba 0.6) from included files too; handing them to Mitsuba as parameters loads the scene as
    clradiosity reads it. Includes are looked up beside the including file and in the main scene's folder."""
    root = os.path.dirname(os.path.abspath(path))
    values, seen, todo = {}, set(), [os.path.abspath(path)]
    while todo:
        current = todo.pop()
        if current in seen or not os.path.isfile(current):
            continue
        seen.add(current)
        try:
            tree = ET.parse(current).getroot()
        except ET.ParseError:
            continue
        if current != os.path.abspath(path):
            for node in tree.iter("default"):
                values.setdefault(node.get("name"), node.get("value"))
        for node in tree.iter("include"):
            name = node.get("filename", "")
            for folder in (os.path.dirname(current), root):
                todo.append(os.path.normpath(os.path.join(folder, name)))
    return values


def without_missing_paths(path):
    """The scene's text less its <path> elements naming folders that are not there, or None where it names none:
    clradiosity warns and ignores such a folder (the corpus ships scenes without the shared folders they take nothing
    from), where Mitsuba refuses the file."""
    folder = os.path.dirname(os.path.abspath(path))
    with open(path, encoding="utf-8") as f:
        text = f.read()
    missing = [m for m in re.finditer(r"<path\s+value=\"([^\"]*)\"\s*/>", text)
               if not os.path.isdir(os.path.join(folder, m.group(1)))]
    for m in reversed(missing):
        text = text[:m.start()] + text[m.end():]
    return text if missing else None


def load(**params):
    text = without_missing_paths(scene_file)
    if text is None:
        return mi.load_file(scene_file, **params)
    # The text loads from a string: its files are looked up in the scene's folder, as load_file would.
    mi.file_resolver().prepend(os.path.dirname(os.path.abspath(scene_file)))
    return mi.load_string(text, **params)


try:
    params = included_defaults(scene_file)
    params["integrator"] = "path"  # scenes whose integrator type is "$integrator"
    try:
        scene = load(**params)
    except Exception:
        params.pop("integrator")
        scene = load(**params)
except Exception as e:
    print(f"Mitsuba cannot load {scene_file}: {e}", file=sys.stderr)
    sys.exit(3)
original = scene.sensors()[0]
camera = mi.traverse(original)
kind = original.class_().name() if hasattr(original, "class_") else type(original).__name__
spec = {
    "to_world": camera["to_world"],
    "near_clip": scalar(camera["near_clip"]),
    # The scene's own reconstruction filter (Mitsuba's gaussian where it names none), as `reference` applies it.
    "film": {"type": "hdrfilm", "width": int(width), "height": int(height), "rfilter": original.film().rfilter()},
}
if "Orthographic" in kind:
    spec["type"] = "orthographic"
else:
    spec.update({"type": "perspective", "fov": scalar(camera["x_fov"]), "fov_axis": "x"})
    if "ThinLens" in kind:
        spec.update({"type": "thinlens", "aperture_radius": scalar(camera["aperture_radius"]),
                     "focus_distance": scalar(camera["focus_distance"])})
    else:  # a lens shift, as fractions of the film: the same at any size
        for key in ("principal_point_offset_x", "principal_point_offset_y"):
            if key in camera:
                spec[key] = scalar(camera[key])
sensor = mi.load_dict(spec)
integrator = mi.load_dict({"type": "path", "max_depth": int(max_depth)})
if count is None:
    mi.Bitmap(mi.render(scene, sensor=sensor, integrator=integrator, spp=int(spp), seed=seed)).write(out)
else:
    stem, ext = os.path.splitext(out)
    for s in range(seed, seed + count):
        image = mi.render(scene, sensor=sensor, integrator=integrator, spp=int(spp), seed=s)
        mi.Bitmap(image).write(f"{stem}-{s}{ext}")
