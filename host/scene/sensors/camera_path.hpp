#pragma once
// Camera paths: the views of a walkthrough, rendered from one trained model (`render --path`, `--orbit`). Every
// frame is the scene's sensor (film, fov axis, clip planes) with another to_world and field of view.
#include <filesystem>
#include <vector>

#include "scene/camera.hpp"
#include "scene/scene.hpp"

namespace clr::scene {

// PATH.json: {"frames": N, "interpolation": "smooth" | "linear", "keyframes": [K ≥ 1 keyframes]}, each keyframe
// either {"origin": [x,y,z], "target": [x,y,z], "up": [x,y,z] (default: the sensor's up), "fov": degrees (default:
// the sensor's)} or {"to_world": [16 numbers, row-major, as Mitsuba's <matrix>], "fov": …}. The keyframes are
// spread evenly over the N frames (the first and last frames are the first and last keyframes). Positions follow
// a Catmull-Rom spline through the keyframes ("smooth", the default) or straight segments ("linear"), orientations
// a slerp between neighbouring keyframes, the fov a straight line. InputError naming the file and key on anything
// malformed: unknown keys, N outside 1 – 100000, a degenerate look-at, a to_world with shear or scale that differs
// between axes, keyframes of both handednesses.
std::vector<Camera> read_camera_path(const std::filesystem::path& file, const Camera& sensor);

// N frames around the vertical axis (the sensor's up) through `centre`, starting at the sensor's view: the sensor's
// whole transform turned by 360°·i/N, so its distance, height and the way it looks at the scene stay.
std::vector<Camera> orbit(const Camera& sensor, const Vec3& centre, int frames);
// The centre of the scene's geometry (its vertices' bounding box; the origin for a scene without shapes): the
// centre `--orbit` turns around.
Vec3 geometry_centre(const std::vector<Shape>& shapes);

}  // namespace clr::scene
