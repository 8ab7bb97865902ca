#pragma once
// A loaded scene: world-space triangle meshes with their BSDFs and area emitters, an optional environment, and
// the camera. Everything the path tracer and the trainer need, independent of Embree (see geometry/).
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "scene/bsdf.hpp"
#include "scene/camera.hpp"
#include "scene/delta_light.hpp"
#include "scene/environment.hpp"
#include "scene/exact_shape.hpp"
#include "scene/mesh.hpp"

namespace clr::scene {

struct Shape {
  std::string id;  // the XML id, or "shape N" (its index) when it has none
  Mesh mesh;       // empty for an exact shape
  std::optional<ExactShape> exact;
  int material = 0;    // index into Scene::materials
  Rgb radiance{0.0f};  // area emitter (emits on the side its shading normal faces); black: none
  // A textured area emitter's radiance over the surface's uv; `radiance` then holds its mean.
  std::optional<Texture> radiance_texture;
  bool is_emitter() const { return !is_black(radiance); }

  // A shape's primitives are its triangles, or the exact shape as one; a point on primitive `prim` is named by `b`:
  // the triangle's barycentrics (weights of its vertices 1 and 2), or the exact shape's uv.
  std::size_t primitive_count() const { return exact ? 1 : mesh.triangles.size(); }
  double primitive_area(std::uint32_t prim) const;
  double area() const;
  TexturePoint texture_point(std::uint32_t prim, const Vec2& b) const {
    return exact ? TexturePoint(b) : mesh.texture_point(prim, b);
  }
  // Grows the box [lo, hi] to hold the shape.
  void extend_bounds(Vec3& lo, Vec3& hi) const;
};

struct Scene {
  std::vector<Shape> shapes;
  // Distinct BSDFs; a shape's material id indexes this list (what the trainer reports as "material id").
  std::vector<std::shared_ptr<const Bsdf>> materials;
  std::unique_ptr<Environment> environment;  // null: black background
  std::vector<DeltaLight> delta_lights;      // point, spot, directional, projector
  Camera camera;
  // The scene's integrator max_depth (longest path in segments, Mitsuba's convention); -1: unbounded.
  int max_depth = -1;
  // Its rr_depth, where it names one: the depth from which the path tracer plays Russian roulette.
  std::optional<int> rr_depth;
  // What the path tracer does with an integrator it does not implement or that wraps another, for `reference` to say
  // (empty: nothing to say).
  std::string integrator_note;
  // The sensor's <sampler> sample_count (Mitsuba's samples per pixel), which `reference` takes when given no --spp;
  // nullopt where the scene names none.
  std::optional<int> sample_count;
  bool has_sensor = false;  // false: `camera` holds defaults, not a view the file chose
  int sensor_count = 0;     // the file's <sensor>s; `camera` and `sample_count` are the chosen one's (load_scene)
  // Every file the scene was read from — the XML first, then includes, meshes, textures and environment maps in the
  // order first read: a command's inputs (no output may replace one) and what a scene's fingerprint covers.
  std::vector<std::filesystem::path> files;
  // Each file's content digest (common/digest.hpp), taken when the loader read it: what the scene was made of, even
  // if the file changes or goes away later (scene/fingerprint.hpp).
  std::vector<std::string> file_digests;
  // The parameters given to load_scene (`-D key=value`) whose value is not the file's own <default>: what makes the
  // same files another scene, so the fingerprint covers them.
  std::map<std::string, std::string> parameters;

  const Bsdf& bsdf(const Shape& s) const { return *materials[std::size_t(s.material)]; }
};

// Loads a Mitsuba scene (versions 0.5–3). `parameters` override the file's <default> values (like mitsuba -D);
// `sensor` picks which of its sensors, in the file's order, is the camera (--sensor, as Mitsuba's sensor index).
// InputError with "file:line: <element>: problem" on any unsupported, missing or malformed input, and naming the
// sensor count when `sensor` is not one of them.
Scene load_scene(const std::filesystem::path& path, const std::map<std::string, std::string>& parameters = {},
                 int sensor = 0);

// What a command needs of a loaded scene, as InputErrors naming the file: light to render or train on (an area
// emitter or an environment; without one every radiance is zero, which is never what was meant), and a sensor to
// render from (training needs none).
void require_emitter(const Scene& scene, const std::filesystem::path& path);
void require_sensor(const Scene& scene, const std::filesystem::path& path);

}  // namespace clr::scene
