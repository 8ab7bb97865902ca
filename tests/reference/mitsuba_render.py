#!/usr/bin/env python3
"""Renders a scene with Mitsuba 3 (scalar_rgb), the independent peer of mitsuba_peer_slow_test.cpp.

Usage: mitsuba_render.py SCENE.xml WIDTH HEIGHT SPP MAX_DEPTH OUT.exr

The scene file is used unchanged: Mitsuba's own `path` integrator (with MAX_DEPTH) replaces whatever the file names
(the shared scenes name integrators Mitsuba does not ship), and the camera is re-created at the requested size with
the loaded sensor's transform and horizontal field of view."""
import sys

import mitsuba as mi

mi.set_variant("scalar_rgb")
scene_file, width, height, spp, max_depth, out = sys.argv[1:7]

try:
    scene = mi.load_file(scene_file, integrator="path")  # scenes whose integrator type is "$integrator"
except Exception:
    scene = mi.load_file(scene_file)
camera = mi.traverse(scene.sensors()[0])
sensor = mi.load_dict({
    "type": "perspective",
    "to_world": camera["to_world"],
    "fov": float(camera["x_fov"][0]) if hasattr(camera["x_fov"], "__len__") else float(camera["x_fov"]),
    "fov_axis": "x",
    "near_clip": float(camera["near_clip"]),
    "film": {"type": "hdrfilm", "width": int(width), "height": int(height), "rfilter": {"type": "box"}},
})
integrator = mi.load_dict({"type": "path", "max_depth": int(max_depth)})
image = mi.render(scene, sensor=sensor, integrator=integrator, spp=int(spp))
mi.Bitmap(image).write(out)
