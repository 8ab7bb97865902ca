#pragma once
// What a plugin reader sees: its element's properties (Props), the loader's services (Context: files, textures,
// nested BSDFs) and the registry that maps a Mitsuba plugin type to its reader, as Mitsuba's plugin factory does.
// A new plugin is one file defining its reader (bsdfs/, emitters/, shapes/, textures/, sensors/) and one line in
// registry.cpp.
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "scene/bsdf.hpp"
#include "scene/camera.hpp"
#include "scene/delta_light.hpp"
#include "scene/environment.hpp"
#include "scene/exact_shape.hpp"
#include "scene/mesh.hpp"
#include "scene/texture.hpp"
#include "scene/xml/xml_source.hpp"

namespace clr::scene::loader {

using xml::Node;

// A plugin element's children: named properties and nested (unnamed) objects. Every named property must be read
// (check_all_used), as Mitsuba 3 demands; files of version 0.x only warn, as Mitsuba 0.x did.
class Props {
 public:
  explicit Props(const Node& plugin);

  std::string type() const { return node.attr("type"); }
  const Node* find(const std::string& name) const;
  bool has(const std::string& name) const { return find(name) != nullptr; }
  void check_all_used() const;

  const Node& expect(const std::string& name, std::initializer_list<const char*> tags) const;
  float number(const std::string& name, float fallback) const;
  int integer(const std::string& name, int fallback) const;
  bool boolean(const std::string& name, bool fallback) const;
  std::string string(const std::string& name, const std::string& fallback) const;
  Rgb color(const std::string& name, const Rgb& fallback) const;
  glm::mat4 transform(const std::string& name) const;
  Vec3 vector3(const std::string& name, const Vec3& fallback) const;
  // Named properties Mitsuba accepts but clradiosity need not read (they change nothing it renders): marked used.
  void ignore(std::initializer_list<const char*> names) const;

  Node node;
  std::map<std::string, Node> named;
  std::vector<Node> objects;  // nested plugins and unnamed <ref>s, in document order
  mutable std::set<std::string> used;
};

// Light and reflectance are never negative nor non-finite: InputError naming the plugin and `property` unless
// `value` is finite and non-negative in every channel (a texture at every texel, not only on average).
void require_non_negative(const Props& p, const std::string& property, const Texture& value);

// An emitter plugin's result: an area emitter's radiance (placed on the shape that holds or references it) or
// light from infinitely far away.
struct EmitterPlugin {
  std::optional<Texture> area;
  std::unique_ptr<Environment> environment;
  std::optional<DeltaLight> delta;
};

// A shape plugin's mesh in its local frame, or an exact unit shape (no mesh); `to_world` may be amended (a sphere's
// radius and centre, a cylinder's ends).
struct ShapePlugin {
  Mesh mesh;
  glm::mat4 to_world{1.0f};
  std::optional<ExactShape::Kind> exact{};  // none: a mesh
};

// The loader's services to plugin readers.
class Context {
 public:
  virtual ~Context() = default;
  // The file a string property names, resolved like Mitsuba's file resolver (the naming file's folder, the
  // <path> folders, the main scene's folder) and required to be a regular file. `what` names it in messages.
  virtual std::filesystem::path file(const Props& p, const std::string& property, const std::string& what) = 0;
  // A texture-valued property (a colour, a nested <texture>, a <ref> to one); `fallback` when absent.
  virtual Texture texture(const Props& p, const std::string& name, const Texture& fallback) = 0;
  // The same for a parameter the BSDF reads as a number (Texture::eval_1: a roughness, a weight, an opacity).
  virtual Texture scalar_texture(const Props& p, const std::string& name, const Texture& fallback) = 0;
  virtual Texture texture(const Node& texture_or_ref) = 0;
  // The BSDFs nested in (or referenced by) a plugin, in document order.
  virtual std::vector<std::shared_ptr<const Bsdf>> nested_bsdfs(const Props& p) = 0;
  // An image texture, loaded once for each way of reading it, its pixels charged to the memory budget first.
  virtual std::shared_ptr<const Bitmap> bitmap(const std::filesystem::path& file, bool raw, float gamma,
                                               Bitmap::Storage storage) = 0;
  // The scene's memory budget (scene/memory_budget.hpp). require_geometry: InputError naming `what` unless `bytes` of
  // geometry more would fit, for a reader to ask before it decodes a mesh (the loader charges each shape once it is
  // built). charge_image: an image file's pixels at `bytes_per_pixel`, sized from its header before it is decoded.
  virtual void require_geometry(std::uint64_t bytes, const std::string& what) = 0;
  virtual void charge_image(const std::filesystem::path& file, std::uint64_t bytes_per_pixel) = 0;
};

std::shared_ptr<const Bsdf> single_nested_bsdf(Context& ctx, const Props& p);
// What Mitsuba's projective cameras (and the projector, their reciprocal) read: `fov` and `fov_axis`, or a
// `focal_length` (default 50 mm on 35 mm film, spanning its diagonal); near_clip, far_clip and focus_distance.
void read_fov(const Props& p, Camera& c);
void read_clip_planes(const Props& p, Camera& c);
// The sensor's <film>: its size and its <rfilter> (Mitsuba's gaussian where it names none).
void read_film(const Props& film, Camera& c);

using BsdfReader = std::shared_ptr<const Bsdf> (*)(Context&, const Props&);
using TextureReader = Texture (*)(Context&, const Props&);
using ShapeReader = ShapePlugin (*)(Context&, const Props&);
using EmitterReader = EmitterPlugin (*)(Context&, const Props&);
using SensorReader = void (*)(Context&, const Props&, Camera&);

// nullptr for a type no plugin reads.
BsdfReader bsdf_reader(const std::string& type);
TextureReader texture_reader(const std::string& type);
ShapeReader shape_reader(const std::string& type);
EmitterReader emitter_reader(const std::string& type);
SensorReader sensor_reader(const std::string& type);
// Mitsuba plugins clradiosity refuses on purpose, with the reason: "kind:type" → why. nullptr: not refused.
const char* refused_plugin(const std::string& kind, const std::string& type);

}  // namespace clr::scene::loader
