// Mitsuba XML → Scene. Plugins are built as their elements are met (document order), ids are global across
// <include>d files, and anything clradiosity does not model is refused with the element's file and line rather
// than silently rendered wrong.
#include <cmath>
#include <set>

#include "common/error.hpp"
#include "image/image.hpp"
#include "scene/bsdfs.hpp"
#include "scene/named_ior.hpp"
#include "scene/scene.hpp"
#include "scene/xml_source.hpp"

namespace clr::scene {
namespace {

using xml::Node;

bool is_value_tag(const std::string& t) {
  return t == "float" || t == "integer" || t == "boolean" || t == "string" || t == "rgb" || t == "srgb" ||
         t == "spectrum" || t == "point" || t == "vector" || t == "transform";
}
bool is_object_tag(const std::string& t) {
  return t == "bsdf" || t == "texture" || t == "emitter" || t == "shape" || t == "sensor" || t == "film" ||
         t == "sampler" || t == "rfilter" || t == "integrator" || t == "ref";
}

// A plugin element's children: named properties and nested (unnamed) objects.
class Props {
 public:
  explicit Props(const Node& plugin) : node(plugin) {
    for (const Node& c : plugin.children()) {
      const std::string t = c.tag();
      if (is_value_tag(t) || ((t == "texture" || t == "ref") && c.has("name"))) {
        const std::string name = c.attr("name");
        if (!named.emplace(name, c).second) c.fail("duplicate property '" + name + "'");
      } else if (is_object_tag(t)) {
        objects.push_back(c);
      } else {
        c.fail("unsupported element");
      }
    }
  }

  const Node* find(const std::string& name) const {
    const auto it = named.find(name);
    if (it == named.end()) return nullptr;
    used.insert(name);
    return &it->second;
  }
  // Like Mitsuba: a property no reader asked for is a misspelling or a feature this plugin lacks, never silently
  // dropped.
  void check_all_used() const {
    for (const auto& [name, n] : named)
      if (!used.count(name)) n.fail("unused property '" + name + "' (misspelt, or not supported by this plugin)");
  }
  bool has(const std::string& name) const { return find(name) != nullptr; }

  const Node& expect(const std::string& name, std::initializer_list<const char*> tags) const {
    const Node* n = find(name);
    if (!n) node.fail("missing property '" + name + "'");
    for (const char* t : tags)
      if (n->tag() == t) return *n;
    n->fail("property '" + name + "' has the wrong type (expected <" + *tags.begin() + ">)");
  }
  float number(const std::string& name, float fallback) const {
    return has(name) ? expect(name, {"float", "integer"}).number("value") : fallback;
  }
  int integer(const std::string& name, int fallback) const {
    if (!has(name)) return fallback;
    const Node& n = expect(name, {"integer"});
    const float v = n.number("value");
    if (v != std::floor(v)) n.fail("expected an integer");
    // Converting a float outside int's range is undefined behaviour, not a large number.
    if (!(std::fabs(v) < 2147483648.0f)) n.fail("integer out of range");
    return int(v);
  }
  bool boolean(const std::string& name, bool fallback) const {
    if (!has(name)) return fallback;
    const Node& n = expect(name, {"boolean"});
    const std::string v = n.attr("value");
    if (v == "true") return true;
    if (v == "false") return false;
    n.fail("expected true or false, got '" + v + "'");
  }
  std::string string(const std::string& name, const std::string& fallback) const {
    return has(name) ? expect(name, {"string"}).attr("value") : fallback;
  }
  Rgb color(const std::string& name, const Rgb& fallback) const {
    return has(name) ? expect(name, {"rgb", "srgb", "spectrum", "float"}).color() : fallback;
  }
  glm::mat4 transform(const std::string& name) const {
    return has(name) ? expect(name, {"transform"}).transform() : glm::mat4(1.0f);
  }

  Node node;
  std::map<std::string, Node> named;
  std::vector<Node> objects;
  mutable std::set<std::string> used;
};

class Loader {
  static constexpr std::size_t kMaxFiles = 1024;

 public:
  explicit Loader(const std::map<std::string, std::string>& parameters) : params_(parameters) {}

  Scene load(const std::filesystem::path& path) {
    load_file(path, nullptr);
    if (scene_.materials.empty()) scene_.materials.push_back(default_bsdf());
    return std::move(scene_);
  }

 private:
  void load_file(const std::filesystem::path& path, const Node* included_from) {
    const auto canonical = std::filesystem::weakly_canonical(path);
    if (!including_.insert(canonical).second) included_from->fail("recursive include of '" + path.string() + "'");
    // Files that each include the next one twice are loaded 2^depth times without any recursion; every parsed
    // file stays in memory (messages point into it). Real scenes include a handful.
    if (included_from && sources_.size() >= kMaxFiles)
      included_from->fail("more than " + std::to_string(kMaxFiles) + " files loaded through <include>");
    std::unique_ptr<xml::Source> src;
    try {
      src = xml::parse_file(path);
    } catch (const InputError& e) {
      if (included_from) included_from->fail(e.what());
      throw;
    }
    const Node root{src->doc.document_element(), src.get(), &params_};
    if (root.xml.empty() || root.tag() != "scene")
      throw InputError(path.string() + ":1: the root element must be <scene>");
    const std::string version = root.attr("version");
    int major = 0;
    if (std::sscanf(version.c_str(), "%d.", &major) != 1 || major < 0 || major > 3)
      root.fail("unsupported scene version '" + version + "' (0.5 to 3 are)");
    src->version_major = major;
    sources_.push_back(std::move(src));
    process(root);
    including_.erase(canonical);
  }

  // Files a scene names must be regular files: a device such as /dev/zero, or a FIFO, would be read forever.
  static void require_file(const Node& n, const std::filesystem::path& f, const std::string& what) {
    std::error_code ec;
    const auto status = std::filesystem::status(f, ec);
    if (!std::filesystem::exists(status)) n.fail(what + " '" + f.string() + "' not found");
    if (!std::filesystem::is_regular_file(status)) n.fail(what + " '" + f.string() + "' is not a regular file");
  }

  std::filesystem::path resolve(const Node& n, const std::string& file) const {
    const std::filesystem::path p(file);
    return p.is_absolute() ? p : n.source->path.parent_path() / p;
  }

  void register_id(const Node& n) {
    if (!n.has("id")) return;
    if (!ids_.insert(n.attr("id")).second) n.fail("duplicate id '" + n.attr("id") + "'");
  }

  void process(const Node& scene) {
    for (const Node& c : scene.children()) {
      const std::string t = c.tag();
      if (t == "default") {
        params_.try_emplace(c.attr("name"), c.attr("value"));
      } else if (t == "include") {
        const auto file = resolve(c, c.attr("filename"));
        require_file(c, file, "included file");
        load_file(file, &c);
      } else if (t == "bsdf") {
        bsdf(c);
      } else if (t == "texture") {
        register_id(c);
        const Texture tex = texture(c);
        if (c.has("id")) textures_[c.attr("id")] = tex;
      } else if (t == "shape") {
        shape(c);
      } else if (t == "emitter") {
        environment(c);
      } else if (t == "sensor") {
        sensor(c);
      } else if (t == "integrator") {
        // clradiosity's own integrators decide how to render; only the path length changes what the image
        // converges to, so it becomes the reference's default (the scenes' reference renders were made with it).
        const Props p(c);
        if (p.has("max_depth")) scene_.max_depth = p.integer("max_depth", -1);
      } else if (t == "sampler" || t == "rfilter" || t == "film") {
        // Read and ignored, like the rest of the integrator.
      } else {
        c.fail("unsupported element");
      }
    }
  }

  // ---- textures -------------------------------------------------------------------------------------------------
  UvTransform uv_transform(const Props& p) const {
    UvTransform t;
    const glm::mat4 m = p.transform("to_uv");
    t.linear = glm::mat2(m[0][0], m[0][1], m[1][0], m[1][1]);
    t.offset = Vec2(m[3][0], m[3][1]);
    // Mitsuba 0.x spelled the same map as scale and offset properties.
    const Vec2 scale(p.number("uscale", 1.0f), p.number("vscale", 1.0f));
    const Vec2 offset(p.number("uoffset", 0.0f), p.number("voffset", 0.0f));
    t.linear = glm::mat2(scale.x, 0, 0, scale.y) * t.linear;
    t.offset = scale * t.offset + offset;
    return t;
  }

  Texture texture(const Node& n) {
    const Props p(n);
    const std::string type = n.attr("type");
    if (type == "bitmap") {
      if (!p.has("filename")) n.fail("missing property 'filename'");
      const auto file = resolve(n, p.string("filename", ""));
      require_file(n, file, "texture file");
      const std::string filter = p.string("filter_type", "bilinear"), wrap = p.string("wrap_mode", "repeat");
      if (filter != "bilinear" && filter != "nearest") n.fail("unsupported filter_type '" + filter + "'");
      if (wrap != "repeat") n.fail("unsupported wrap_mode '" + wrap + "' (only repeat)");
      const bool raw = p.boolean("raw", false);
      auto& cached = bitmaps_[{file.string(), raw}];
      if (!cached) cached = Bitmap::load(file, raw);
      const Texture t = Texture::bitmap(cached, uv_transform(p), filter == "bilinear");
      p.check_all_used();
      return t;
    }
    if (type == "checkerboard") {
      const Texture t =
          Texture::checkerboard(p.color("color0", Rgb(0.4f)), p.color("color1", Rgb(0.2f)), uv_transform(p));
      p.check_all_used();
      return t;
    }
    n.fail("unsupported texture type '" + type + "'");
  }

  Texture texture_property(const Props& p, const std::string& name, const Rgb& fallback) {
    const Node* n = p.find(name);
    if (!n) return fallback;
    if (n->tag() == "texture") return texture(*n);
    if (n->tag() == "ref") {
      const auto it = textures_.find(n->attr("id"));
      if (it == textures_.end()) n->fail("reference to unknown texture id '" + n->attr("id") + "'");
      return it->second;
    }
    return n->color();
  }

  // ---- BSDFs ----------------------------------------------------------------------------------------------------
  std::shared_ptr<const Bsdf> default_bsdf() {
    if (!default_bsdf_) default_bsdf_ = std::make_shared<Diffuse>(Texture(Rgb(0.5f)));
    return default_bsdf_;
  }

  std::shared_ptr<const Bsdf> bsdf_reference(const Node& ref) {
    const std::string id = ref.attr("id");
    const auto it = bsdfs_.find(id);
    if (it != bsdfs_.end()) return it->second;
    if (ids_.count(id)) ref.fail("id '" + id + "' does not name a BSDF");
    ref.fail("reference to unknown id '" + id + "'");
  }

  std::vector<std::shared_ptr<const Bsdf>> nested_bsdfs(const Props& p) {
    std::vector<std::shared_ptr<const Bsdf>> out;
    for (const Node& o : p.objects) {
      if (o.tag() == "bsdf")
        out.push_back(bsdf(o));
      else if (o.tag() == "ref")
        out.push_back(bsdf_reference(o));
      else if (o.tag() != "texture")
        o.fail("unexpected inside a BSDF");
    }
    return out;
  }

  std::shared_ptr<const Bsdf> single_nested(const Props& p) {
    auto nested = nested_bsdfs(p);
    if (nested.size() != 1) p.node.fail("expects exactly one nested BSDF");
    return nested.front();
  }

  float ior(const Props& p, const std::string& name, float fallback) const {
    const Node* n = p.find(name);
    if (!n) return fallback;
    if (n->tag() == "string") {
      const auto v = dielectric_ior(n->attr("value"));
      if (!v) n->fail("unknown IOR name '" + n->attr("value") + "'");
      return *v;
    }
    const float v = p.number(name, fallback);
    if (!(v > 0)) n->fail("an IOR must be positive");
    return v;
  }

  std::optional<Microfacet> microfacet(const Props& p) const {
    Microfacet mf;
    const std::string d = p.string("distribution", "beckmann");
    if (d == "beckmann")
      mf.type = Microfacet::Type::beckmann;
    else if (d == "ggx")
      mf.type = Microfacet::Type::ggx;
    else
      p.expect("distribution", {"string"}).fail("unsupported distribution '" + d + "' (beckmann, ggx)");
    if (p.has("alpha_u") || p.has("alpha_v")) {
      const float au = p.number("alpha_u", 0.1f), av = p.number("alpha_v", 0.1f);
      if (au != av) p.node.fail("anisotropic roughness is not supported");
      mf.alpha = au;
    } else {
      mf.alpha = p.number("alpha", 0.1f);
    }
    // Below 1e-4 the lobe is numerically a delta; a mirror would be the better model.
    if (!(mf.alpha >= 1e-4f)) p.node.fail("alpha must be at least 1e-4");
    return mf;
  }

  std::shared_ptr<const Bsdf> bsdf(const Node& n) {
    register_id(n);
    const Props p(n);
    const std::string type = n.attr("type");
    std::shared_ptr<const Bsdf> b;
    if (type == "diffuse") {
      b = std::make_shared<Diffuse>(texture_property(p, "reflectance", Rgb(0.5f)));
    } else if (type == "twosided") {
      auto nested = nested_bsdfs(p);
      if (nested.empty() || nested.size() > 2) n.fail("twosided expects one or two nested BSDFs");
      b = std::make_shared<TwoSided>(nested.front(), nested.back());
    } else if (type == "conductor" || type == "roughconductor") {
      ComplexIor c{Rgb(0.0f), Rgb(1.0f)};
      if (p.has("eta") || p.has("k")) {
        c = {p.color("eta", Rgb(0.0f)), p.color("k", Rgb(1.0f))};
      } else {
        const std::string m = p.string("material", "none");
        const auto named = conductor_ior(m);
        if (!named) p.expect("material", {"string"}).fail("unknown conductor material '" + m + "'");
        c = *named;
      }
      const float ext = p.number("ext_eta", 1.0f);
      b = std::make_shared<Conductor>(c.eta / ext, c.k / ext, texture_property(p, "specular_reflectance", Rgb(1.0f)),
                                      type == "roughconductor" ? microfacet(p) : std::nullopt);
    } else if (type == "plastic" || type == "roughplastic") {
      const float eta = ior(p, "int_ior", 1.49f) / ior(p, "ext_ior", 1.000277f);
      b = std::make_shared<Plastic>(eta, texture_property(p, "diffuse_reflectance", Rgb(0.5f)),
                                    texture_property(p, "specular_reflectance", Rgb(1.0f)),
                                    p.boolean("nonlinear", false),
                                    type == "roughplastic" ? microfacet(p) : std::nullopt);
    } else if (type == "dielectric" || type == "thindielectric" || type == "roughdielectric") {
      const float eta = ior(p, "int_ior", 1.5046f) / ior(p, "ext_ior", 1.000277f);
      const auto kind = type == "dielectric"       ? Dielectric::Kind::smooth
                        : type == "thindielectric" ? Dielectric::Kind::thin
                                                   : Dielectric::Kind::rough;
      b = std::make_shared<Dielectric>(kind, eta, texture_property(p, "specular_reflectance", Rgb(1.0f)),
                                       texture_property(p, "specular_transmittance", Rgb(1.0f)),
                                       kind == Dielectric::Kind::rough ? microfacet(p) : std::nullopt);
    } else if (type == "mask") {
      b = std::make_shared<Mask>(texture_property(p, "opacity", Rgb(0.5f)), single_nested(p));
    } else if (type == "bumpmap") {
      BumpMap bump;
      bump.scale = p.number("scale", 1.0f);
      const Node* height = nullptr;
      for (const auto& [name, node] : p.named)
        if (node.tag() == "texture" || node.tag() == "ref") height = p.find(name);  // any name: Mitsuba's is free
      for (const Node& o : p.objects)
        if (o.tag() == "texture") height = &o;
      if (!height) n.fail("bumpmap needs a height texture");
      if (height->tag() == "texture")
        bump.height = texture(*height);
      else
        bump.height = texture_property(p, height->attr("name"), Rgb(0.0f));
      b = std::make_shared<BumpMapped>(bump, single_nested(p));
    } else {
      n.fail("unsupported BSDF type '" + type + "'");
    }
    p.check_all_used();
    if (n.has("id")) bsdfs_[n.attr("id")] = b;
    return b;
  }

  int material_index(const std::shared_ptr<const Bsdf>& b) {
    const auto [it, inserted] = material_ids_.try_emplace(b.get(), int(scene_.materials.size()));
    if (inserted) scene_.materials.push_back(b);
    return it->second;
  }

  // ---- shapes, emitters, sensor ---------------------------------------------------------------------------------
  void shape(const Node& n) {
    register_id(n);
    const Props p(n);
    const std::string type = n.attr("type");
    Shape s;
    s.id = n.attr_or("id", "shape " + std::to_string(scene_.shapes.size()));
    glm::mat4 to_world = p.transform("to_world");
    auto file = [&] {
      if (!p.has("filename")) n.fail("missing property 'filename'");
      const auto f = resolve(n, p.string("filename", ""));
      require_file(n, f, "mesh file");
      return f;
    };
    try {
      if (type == "obj") {
        s.mesh = load_obj(file());
      } else if (type == "ply") {
        s.mesh = load_ply(file());
      } else if (type == "serialized") {
        s.mesh = load_serialized(file(), p.integer("shape_index", 0));
      } else if (type == "rectangle") {
        s.mesh = make_rectangle();
      } else if (type == "cube") {
        s.mesh = make_cube();
      } else if (type == "disk") {
        s.mesh = make_disk();
      } else if (type == "sphere") {
        s.mesh = make_sphere();
        const float radius = p.number("radius", 1.0f);
        if (!(radius > 0)) p.expect("radius", {"float"}).fail("radius must be positive");
        const Vec3 center = p.has("center") ? p.expect("center", {"point", "vector"}).vector3() : Vec3(0.0f);
        to_world = to_world * glm::mat4(glm::vec4(radius, 0, 0, 0), glm::vec4(0, radius, 0, 0),
                                        glm::vec4(0, 0, radius, 0), glm::vec4(center, 1));
      } else {
        n.fail("unsupported shape type '" + type + "'");
      }
    } catch (const InputError& e) {
      if (std::string(e.what()).starts_with(n.where())) throw;
      n.fail(e.what());  // a mesh file's own message, prefixed with the element that named it
    }
    const bool file_mesh = type == "obj" || type == "ply" || type == "serialized";
    if (file_mesh && !p.boolean("flip_tex_coords", true))
      for (auto& uv : s.mesh.uvs) uv.y = 1.0f - uv.y;
    if (p.boolean("face_normals", false)) s.mesh.normals.clear();
    // Mitsuba gives meshes without normals smooth ones unless face_normals asks for flat shading.
    else if (file_mesh && s.mesh.normals.empty())
      s.mesh.compute_vertex_normals();
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(to_world[c][r])) n.fail("the to_world transform is not finite (it overflows)");
    // A singular to_world (a zero scale) flattens the mesh and leaves its normals undefined.
    if (!(std::fabs(glm::determinant(glm::mat3(to_world))) > 0))
      n.fail("the to_world transform is singular (a zero scale?)");
    s.mesh.transform(to_world);
    if (p.boolean("flip_normals", false)) s.mesh.flip();
    s.mesh.validate(n.where());

    std::shared_ptr<const Bsdf> b;
    for (const Node& o : p.objects) {
      const std::string t = o.tag();
      if (t == "bsdf" || t == "ref") {
        if (b) o.fail("a shape has one BSDF");
        b = t == "bsdf" ? bsdf(o) : bsdf_reference(o);
      } else if (t == "emitter") {
        const Props e(o);
        if (o.attr("type") != "area") o.fail("only area emitters can be attached to shapes");
        if (s.is_emitter()) o.fail("a shape has one emitter");
        if (e.has("radiance") && e.find("radiance")->tag() == "texture") o.fail("textured radiance is not supported");
        s.radiance = e.color("radiance", Rgb(1.0f));
        e.check_all_used();
        if (!(s.radiance.x >= 0 && s.radiance.y >= 0 && s.radiance.z >= 0)) o.fail("radiance must be non-negative");
      } else {
        o.fail("unexpected inside a shape");
      }
    }
    p.check_all_used();
    s.material = material_index(b ? b : default_bsdf());
    scene_.shapes.push_back(std::move(s));
  }

  void environment(const Node& n) {
    register_id(n);
    const Props p(n);
    const std::string type = n.attr("type");
    if (scene_.environment) n.fail("a scene has at most one environment emitter");
    if (type == "constant") {
      const Rgb radiance = p.color("radiance", Rgb(1.0f));
      if (!(radiance.x >= 0 && radiance.y >= 0 && radiance.z >= 0)) n.fail("radiance must be non-negative");
      scene_.environment = std::make_unique<Environment>(Environment::constant(radiance));
    } else if (type == "envmap") {
      if (!p.has("filename")) n.fail("missing property 'filename'");
      const auto file = resolve(n, p.string("filename", ""));
      require_file(n, file, "environment map");
      try {
        scene_.environment =
            std::make_unique<Environment>(Environment::envmap(file, p.number("scale", 1.0f), p.transform("to_world")));
      } catch (const InputError& e) {
        n.fail(e.what());
      }
    } else if (type == "area") {
      n.fail("an area emitter must be nested in a shape");
    } else {
      n.fail("unsupported emitter type '" + type + "'");
    }
    p.check_all_used();
  }

  void sensor(const Node& n) {
    register_id(n);
    const Props p(n);
    if (n.attr("type") != "perspective") n.fail("unsupported sensor type '" + n.attr("type") + "' (perspective)");
    if (sensor_seen_) n.fail("a scene has one sensor");
    sensor_seen_ = true;
    scene_.has_sensor = true;
    Camera& c = scene_.camera;
    if (!p.has("fov")) n.fail("the perspective sensor needs a 'fov'");
    c.fov_degrees = p.number("fov", 45.0f);
    if (!(c.fov_degrees > 0 && c.fov_degrees < 180)) p.expect("fov", {"float"}).fail("fov must lie in (0, 180)");
    const std::string axis = p.string("fov_axis", "x");
    if (axis == "x")
      c.fov_axis = Camera::FovAxis::x;
    else if (axis == "y")
      c.fov_axis = Camera::FovAxis::y;
    else if (axis == "diagonal")
      c.fov_axis = Camera::FovAxis::diagonal;
    else if (axis == "smaller")
      c.fov_axis = Camera::FovAxis::smaller;
    else if (axis == "larger")
      c.fov_axis = Camera::FovAxis::larger;
    else
      p.expect("fov_axis", {"string"}).fail("unsupported fov_axis '" + axis + "'");
    c.near_clip = p.number("near_clip", 1e-2f);
    c.to_world = p.transform("to_world");
    p.check_all_used();
    for (const Node& o : p.objects) {
      if (o.tag() != "film") continue;
      const Props f(o);
      c.width = f.integer("width", 768);
      c.height = f.integer("height", 576);
      try {
        image::check_image_size(c.width, c.height, "film");
      } catch (const InputError& e) {
        o.fail(e.what());
      }
    }
  }

  std::vector<std::unique_ptr<xml::Source>> sources_;
  std::map<std::string, std::string> params_;
  std::set<std::filesystem::path> including_;
  std::set<std::string> ids_;
  std::map<std::string, std::shared_ptr<const Bsdf>> bsdfs_;
  std::map<std::string, Texture> textures_;
  std::map<std::pair<std::string, bool>, std::shared_ptr<const Bitmap>> bitmaps_;
  std::map<const Bsdf*, int> material_ids_;
  std::shared_ptr<const Bsdf> default_bsdf_;
  bool sensor_seen_ = false;
  Scene scene_;
};

}  // namespace

Scene load_scene(const std::filesystem::path& path, const std::map<std::string, std::string>& parameters) {
  return Loader(parameters).load(path);
}

void require_emitter(const Scene& scene, const std::filesystem::path& path) {
  if (scene.environment) return;
  // A shape whose triangles are all degenerate is a valid part of a scene (it is never hit), but no light.
  for (const auto& s : scene.shapes)
    if (s.is_emitter() && s.mesh.area() > 0) return;
  throw InputError(path.string() +
                   ": the scene has no emitter (an area emitter on a shape of non-zero area, or an "
                   "environment): every radiance would be zero");
}

void require_sensor(const Scene& scene, const std::filesystem::path& path) {
  if (!scene.has_sensor) throw InputError(path.string() + ": the scene has no <sensor> to render from");
  scene.camera.validate(path.string() + ": <sensor>");
}

}  // namespace clr::scene
