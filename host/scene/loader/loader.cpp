// Mitsuba XML → Scene: the walk over the document. Plugins are built as their elements are met (document order),
// each by the reader the registry names for its type (registry.cpp); ids are global across <include>d files, and
// anything clradiosity does not model is refused with the element's file and line rather than silently rendered
// wrong.
#include <cmath>
#include <cstdio>
#include <optional>
#include <set>
#include <tuple>

#include "common/digest.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "common/terminal_text.hpp"
#include "image/image.hpp"
#include "scene/bsdfs.hpp"
#include "scene/loader/plugin.hpp"
#include "scene/memory_budget.hpp"
#include "scene/scene.hpp"

namespace clr::scene {
namespace {

using loader::Node;
using loader::Props;

// Mesh attributes named by mesh_attribute textures: attribute → the id of a texture naming it and, where one is
// read as a number (Texture::eval_1), that parameter's name.
struct AttributeUse {
  std::string texture, as_number;
};
using AttributeUses = std::map<std::string, AttributeUse>;

// Adds `use` of `attribute` to `uses`; a read as a number is kept over a read as a colour.
void add_use(AttributeUses& uses, const std::string& attribute, const AttributeUse& use) {
  const auto [it, added] = uses.try_emplace(attribute, use);
  if (!added && it->second.as_number.empty()) it->second.as_number = use.as_number;
}

class Loader final : public loader::Context {
  static constexpr std::size_t kMaxFiles = 1024;
  // The loader recurses through <include>s, BSDFs nested in BSDFs and <ref>s to plugins declared further down
  // (each built where it is first referenced): XML nesting alone is bounded by the parser, but a chain of forward
  // references is not, and 10 000 of them overflowed the stack. Real scenes nest a handful.
  static constexpr int kMaxBuildDepth = 128;
  // A BSDF evaluates the BSDFs it nests, and a referenced BSDF may be nested many times over: a chain of blends
  // each nesting the previous one twice costs 2^n evaluations per sample. Both the depth and the number of BSDFs
  // an evaluation may visit are bounded.
  static constexpr int kMaxBsdfDepth = 32;
  static constexpr std::size_t kMaxBsdfVisits = 1024;
  // Triangles the whole scene may hold, instances' copies included: each costs its mesh and Embree's structures
  // (more than 100 bytes), so 2^25 is several GiB. Counted as shapes are built, so that an instance bomb (a large
  // group instanced thousands of times) is refused before its copies are made, naming the element that crossed it.
  static constexpr std::size_t kMaxSceneTriangles = std::size_t(1) << 25;

  // Counts one level of the loader's recursion while alive; refuses (naming the element) beyond kMaxBuildDepth.
  class Deeper {
   public:
    Deeper(int& depth, const Node& n) : depth_(depth) {
      if (++depth_ > kMaxBuildDepth) {
        --depth_;
        n.fail("plugins nested deeper than " + std::to_string(kMaxBuildDepth) +
               " levels (through <include>s, nested BSDFs and <ref>s to plugins declared further down)");
      }
    }
    ~Deeper() { --depth_; }
    Deeper(const Deeper&) = delete;
    Deeper& operator=(const Deeper&) = delete;

   private:
    int& depth_;
  };

 public:
  Loader(const std::map<std::string, std::string>& parameters, int sensor)
      : params_{parameters, {}}, given_(parameters), sensor_(sensor) {}

  Scene load(const std::filesystem::path& path) {
    scene_folder_ = path.parent_path();
    load_file(path, nullptr);
    if (sensor_ < 0 || sensor_ >= std::max(1, scene_.sensor_count))
      throw InputError("--sensor " + std::to_string(sensor_) + ": " + path.string() + " has " +
                       std::to_string(scene_.sensor_count) + " sensor" + (scene_.sensor_count == 1 ? "" : "s") +
                       (scene_.sensor_count > 1 ? " (0 to " + std::to_string(scene_.sensor_count - 1) + ")" : ""));
    for (const auto& [name, value] : given_) {
      // As Mitsuba 3 ("Found unused parameters"): a key the scene never substitutes is a typo, or another scene's.
      if (!params_.used.contains(name))
        throw InputError("-D " + clip(name) + "=" + clip(value) + ": " + path.string() + " never uses $" + clip(name) +
                         " (as Mitsuba, a parameter the scene does not use is refused)");
      if (const auto d = defaults_.find(name); d == defaults_.end() || d->second != value)
        scene_.parameters[name] = value;
    }
    if (scene_.materials.empty()) scene_.materials.push_back(default_bsdf());
    return std::move(scene_);
  }

  // ---- services to the plugin readers ---------------------------------------------------------------------------
  std::filesystem::path file(const Props& p, const std::string& property, const std::string& what) override {
    if (!p.has(property)) p.node.fail("missing property '" + property + "'");
    const Node& n = p.expect(property, {"string"});
    const auto f = resolve(n, n.attr("value"));
    require_file(p.node, f, what);
    record(f);
    return f;
  }

  Texture texture(const Props& p, const std::string& name, const Texture& fallback) override {
    const Node* n = p.find(name);
    if (!n) return fallback;
    const Texture t = n->tag() == "texture" || n->tag() == "ref" ? texture(*n) : Texture(n->color());
    // What scales light (reflectances, transmittances, a base colour, a blend's weight, a mask's opacity) must
    // be non-negative at every texel: a negative texel would emit negative light wherever it is seen. Roughness,
    // normal and bump maps are checked by their readers.
    if (name.ends_with("reflectance") || name.ends_with("transmittance") || name == "base_color" || name == "weight" ||
        name == "opacity")
      require_non_negative(p, name, t);
    return t;
  }
  Texture scalar_texture(const Props& p, const std::string& name, const Texture& fallback) override {
    const Texture t = texture(p, name, fallback);
    record_use(t, name);
    return t;
  }

  Texture texture(const Node& n) override {
    if (n.tag() == "ref") {
      build_declared(n.attr("id"));
      const auto it = textures_.find(n.attr("id"));
      if (it == textures_.end()) n.fail("reference to unknown texture id '" + n.attr("id") + "'");
      record_use(it->second);
      return it->second;
    }
    register_id(n, "texture");
    if (const char* why = loader::refused_plugin("texture", n.attr_or("type", ""))) n.fail(why);
    const Props p(n);
    const auto reader = loader::texture_reader(p.type());
    if (!reader) n.fail("unsupported texture type '" + p.type() + "'");
    const Texture t = reader(*this, p);
    p.check_all_used();
    if (n.has("id")) textures_[n.attr("id")] = t;
    record_use(t);
    return t;
  }

  std::vector<std::shared_ptr<const Bsdf>> nested_bsdfs(const Props& p) override {
    std::vector<std::shared_ptr<const Bsdf>> out;
    for (const Node& o : p.objects) {
      if (o.tag() == "bsdf")
        out.push_back(bsdf(o));
      else if (o.tag() == "ref")
        out.push_back(bsdf_reference(o));
      else if (o.tag() != "texture")
        o.fail("unexpected inside a BSDF");
    }
    // A named reference to a BSDF (<ref name="bsdf" id=".."/>) nests it too; named textures are read by name.
    for (const auto& [name, n] : p.named) {
      if (n.tag() != "ref") continue;
      build_declared(n.attr("id"));
      if (bsdfs_.count(n.attr("id"))) out.push_back(bsdf_reference(*p.find(name)));
    }
    if (!nesting_.empty()) nesting_.back().insert(nesting_.back().end(), out.begin(), out.end());
    return out;
  }

  std::shared_ptr<const Bitmap> bitmap(const std::filesystem::path& file, bool raw, float gamma,
                                       Bitmap::Storage storage) override {
    auto& cached = bitmaps_[{file.string(), raw, gamma, storage}];
    if (!cached) {
      charge_image(file, kBytesPerTexel);
      cached = Bitmap::load(file, raw, gamma, storage);
    }
    return cached;
  }

  void require_geometry(std::uint64_t bytes, const std::string& what) override {
    budget_.require(bytes, MemoryBudget::Part::geometry, what);
  }

  void charge_image(const std::filesystem::path& file, std::uint64_t bytes_per_pixel) override {
    const auto [w, h] = image::image_file_size(file);
    budget_.charge(std::uint64_t(w) * std::uint64_t(h) * bytes_per_pixel, MemoryBudget::Part::images,
                   "image " + file.string());
  }

 private:
  // Every file the scene reads, once each, in the order first read (Scene::files).
  void record(const std::filesystem::path& file) {
    if (!recorded_.insert(std::filesystem::weakly_canonical(file)).second) return;
    scene_.files.push_back(file);
    scene_.file_digests.push_back(Digest().add_file(file).hex());
  }

  void load_file(const std::filesystem::path& path, const Node* included_from) {
    const auto canonical = std::filesystem::weakly_canonical(path);
    if (!including_.insert(canonical).second) included_from->fail("recursive include of '" + path.string() + "'");
    std::optional<Deeper> deeper;
    if (included_from) deeper.emplace(depth_, *included_from);
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
    record(path);
    const Node root{src->doc.document_element(), src.get(), &params_};
    if (root.xml.empty() || root.tag() != "scene")
      throw InputError(path.string() + ":1: the root element must be <scene>");
    const std::string version = root.attr("version");
    int major = 0;
    if (std::sscanf(version.c_str(), "%d.", &major) != 1 || major < 0 || major > 3)
      root.fail("unsupported scene version '" + version + "' (0.5 to 3 are)");
    src->version_major = major;
    sources_.push_back(std::move(src));
    // Mitsuba resolves references after reading the whole file, so a <ref> may name a plugin declared further
    // down: such a plugin is built when first referenced, and skipped when the walk reaches it.
    for (const Node& c : root.children())
      if (c.has("id")) declared_.try_emplace(c.attr("id"), c);
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

  // Mitsuba's file resolver: a relative name is looked up in the folders of <path> elements (latest first) and the
  // main scene's folder; the naming file's own folder comes first, so that included files may name their
  // neighbours. The first candidate that exists wins; none: the naming file's folder (its message names it).
  std::filesystem::path resolve(const Node& n, const std::string& file) const {
    const std::filesystem::path p(file);
    if (p.is_absolute()) return p;
    const auto own = n.source->path.parent_path() / p;
    std::error_code ec;
    if (std::filesystem::exists(own, ec)) return own;
    for (auto it = search_folders_.rbegin(); it != search_folders_.rend(); ++it)
      if (std::filesystem::exists(*it / p, ec)) return *it / p;
    if (std::filesystem::exists(scene_folder_ / p, ec)) return scene_folder_ / p;
    return own;
  }

  // What a material or emitter reads of its shape's mesh: the uses of the textures read while `build` runs (nested
  // and referenced materials included) are gathered into `uses`.
  template <typename Build>
  auto gathering_uses(AttributeUses& uses, Build build) {
    attribute_scopes_.emplace_back();
    auto made = build();
    uses = std::move(attribute_scopes_.back());
    attribute_scopes_.pop_back();
    return made;
  }
  void record_uses(const AttributeUses& uses) {
    for (auto& scope : attribute_scopes_)
      for (const auto& [attribute, use] : uses) add_use(scope, attribute, use);
  }
  void record_use(const Texture& t, const std::string& as_number = "") {
    for (auto& scope : attribute_scopes_) record_use(t, scope, as_number);
  }
  static void record_use(const Texture& t, AttributeUses& uses, const std::string& as_number = "") {
    if (!t.attribute().empty()) add_use(uses, t.attribute(), {t.id(), as_number});
  }

  void register_id(const Node& n, const std::string& kind) {
    if (!n.has("id")) return;
    if (!ids_.emplace(n.attr("id"), kind).second) n.fail("duplicate id '" + n.attr("id") + "'");
  }

  // Builds the top-level plugin `id` names if it is declared but not built yet (a forward reference).
  void build_declared(const std::string& id) {
    const auto it = declared_.find(id);
    if (it == declared_.end() || !built_.insert(it->second.xml.internal_object()).second) return;
    const Node n = it->second;
    const Deeper deeper(depth_, n);
    const std::string t = n.tag();
    if (t == "bsdf")
      bsdf(n);
    else if (t == "texture")
      texture(n);
    else if (t == "emitter")
      emitter(n);
    else if (t == "shape")
      shape(n);
  }

  void process(const Node& scene) {
    for (const Node& c : scene.children()) {
      const std::string t = c.tag();
      if (c.has("id") && !built_.insert(c.xml.internal_object()).second) continue;  // built when referenced
      if (t == "default") {
        params_.values.try_emplace(c.attr("name"), c.attr("value"));
        defaults_.try_emplace(c.attr("name"), c.attr("value"));
      } else if (t == "include") {
        const auto file = resolve(c, c.attr("filename"));
        require_file(c, file, "included file");
        load_file(file, &c);
      } else if (t == "path") {
        // Mitsuba's <path value="folder"/>: one more folder where file names are looked up.
        const auto folder = resolve(c, c.attr("value"));
        std::error_code ec;
        // A folder that is not there can hold no file: the scene loads as long as no file is looked up in vain
        // (real scenes ship without the shared folders they use nothing from).
        if (std::filesystem::is_directory(folder, ec))
          search_folders_.push_back(folder);
        else
          std::fprintf(stderr, "%s: warning: folder '%s' not found\n", clr::terminal_safe(c.where()).c_str(),
                       clr::terminal_safe(folder.string()).c_str());
      } else if (t == "bsdf") {
        bsdf(c);
      } else if (t == "texture") {
        texture(c);
      } else if (t == "shape") {
        shape(c);
      } else if (t == "emitter") {
        emitter(c);
      } else if (t == "sensor") {
        sensor(c);
      } else if (t == "integrator") {
        integrator(c, true);
      } else if (t == "sampler" || t == "rfilter" || t == "film") {
        // Read and ignored, like the rest of the integrator.
      } else if (const char* why = loader::refused_plugin(t, c.attr_or("type", ""))) {
        c.fail(why);
      } else {
        c.fail("unsupported element");
      }
    }
  }

  // The scene's integrator sets what `reference` converges to: the innermost light-transport integrator (an `aov` or
  // `moment` wrapper renders the one nested in it) with its path length — `path` and its kin their max_depth,
  // `direct` emission plus one bounce — and roulette depth. Training solves the whole transport whatever it says.
  // Integrators that need what clradiosity does not model (polarization) are refused; others it does not implement
  // are rendered as `path`; `reference` says so in one line (Scene::integrator_note).
  void integrator(const Node& n, bool top) {
    if (const char* why = loader::refused_plugin("integrator", n.attr_or("type", ""))) n.fail(why);
    for (const Node& c : n.children())
      if (c.tag() == "integrator") integrator(c, false);
    if (!top) return;
    Node transport = n;  // Nodes are handles into the parsed file: copies are cheap
    for (bool wrapper = true; wrapper;) {
      wrapper = false;
      for (const Node& c : transport.children())
        if (c.tag() == "integrator") {
          transport = c;
          wrapper = true;
          break;
        }
    }
    const std::string type = transport.attr_or("type", "");
    const Props p(transport);
    // Mitsuba 3's path tracers (and their 0.x names): the same converged image for a given max_depth.
    static const std::set<std::string> paths = {
        "path",           "volpath",           "volpathmis", "prb",  "prbvolpath",    "prb_basic",
        "prb_projective", "direct_projective", "ptracer",    "bdpt", "pssmlt",        "mlt",
        "erpt",           "photonmapper",      "sppm",       "ppm",  "volpath_simple"};
    scene_.max_depth = -1;
    scene_.rr_depth.reset();
    scene_.integrator_note.clear();
    if (type == "direct") {
      // Emitted light plus one bounce of direct light: the path tracer's two-segment paths (Mitsuba's emitter and
      // BSDF sample counts change its noise, not its image).
      scene_.max_depth = 2;
    } else if (paths.count(type)) {
      if (p.has("max_depth")) scene_.max_depth = p.integer("max_depth", -1);
      if (p.has("rr_depth")) scene_.rr_depth = p.integer("rr_depth", 5);
    } else {
      scene_.integrator_note = transport.where() + ": integrator '" + type +
                               "' is not implemented: the path tracer renders it as 'path'" +
                               (p.has("max_depth") ? " with its max_depth" : "");
      if (p.has("max_depth")) scene_.max_depth = p.integer("max_depth", -1);
    }
    if (scene_.integrator_note.empty() && transport.where() != n.where())
      scene_.integrator_note = n.where() + ": integrator '" + n.attr_or("type", "") + "' wraps '" + type +
                               "': the path tracer renders the inner one";
    if (scene_.max_depth < -1)
      p.expect("max_depth", {"integer"}).fail("max_depth must be -1 (unbounded) or at least 0");
    if (scene_.rr_depth && *scene_.rr_depth < 1) p.expect("rr_depth", {"integer"}).fail("rr_depth must be at least 1");
  }

  // ---- BSDFs ----------------------------------------------------------------------------------------------------
  // A shape without a BSDF is diffuse 0.5, an emitting one black: Mitsuba (0.6 and 3) gives a light source an
  // all-absorbing default, so that a lamp does not reflect the light of the room it lights.
  std::shared_ptr<const Bsdf> default_bsdf(bool emitter = false) {
    auto& b = default_bsdfs_[emitter ? 1 : 0];
    if (!b) b = std::make_shared<Diffuse>(Texture(Rgb(emitter ? 0.0f : 0.5f)));
    return b;
  }

  std::shared_ptr<const Bsdf> bsdf_reference(const Node& ref) {
    const std::string id = ref.attr("id");
    build_declared(id);
    const auto it = bsdfs_.find(id);
    if (it != bsdfs_.end()) {
      record_uses(bsdf_uses_[it->second.get()]);
      return it->second;
    }
    if (ids_.count(id)) ref.fail("id '" + id + "' does not name a BSDF");
    ref.fail("reference to unknown id '" + id + "'");
  }

  std::shared_ptr<const Bsdf> bsdf(const Node& n) {
    const Deeper deeper(depth_, n);
    register_id(n, "bsdf");
    const Props p(n);
    const std::string type = p.type();
    if (const char* why = loader::refused_plugin("bsdf", type)) n.fail(why);
    const auto reader = loader::bsdf_reader(type);
    if (!reader) n.fail("unsupported BSDF type '" + type + "'");
    AttributeUses uses;
    nesting_.emplace_back();
    const auto b = gathering_uses(uses, [&] { return reader(*this, p); });
    BsdfExtent extent;
    for (const auto& nested : nesting_.back()) {
      const auto it = extents_.find(nested.get());
      const BsdfExtent e = it == extents_.end() ? BsdfExtent{} : it->second;
      extent.depth = std::max(extent.depth, e.depth + 1);
      extent.visits += e.visits;
    }
    nesting_.pop_back();
    if (extent.depth > kMaxBsdfDepth)
      n.fail("BSDFs nested " + std::to_string(extent.depth) + " deep (through references), more than " +
             std::to_string(kMaxBsdfDepth));
    if (extent.visits > kMaxBsdfVisits)
      n.fail("the BSDF nests " + std::to_string(extent.visits) + " BSDFs in all (references counted each time), " +
             "more than " + std::to_string(kMaxBsdfVisits) + ": each evaluation would visit every one");
    extents_[b.get()] = extent;
    bsdf_uses_[b.get()] = uses;
    p.check_all_used();
    if (n.has("id")) bsdfs_[n.attr("id")] = b;
    return b;
  }

  int material_index(const std::shared_ptr<const Bsdf>& b) {
    const auto [it, inserted] = material_ids_.try_emplace(b.get(), int(scene_.materials.size()));
    if (inserted) scene_.materials.push_back(b);
    return it->second;
  }

  // ---- shapes ---------------------------------------------------------------------------------------------------
  void shape(const Node& n) {
    const std::string type = n.attr_or("type", "");
    if (type == "shapegroup") return shapegroup(n);
    if (type == "instance") return instance(n);
    scene_.shapes.push_back(build_shape(n));
    count_triangles(n, scene_.shapes.back().primitive_count());
    charge(n, scene_.shapes.back());
  }

  // Bytes a built shape holds, with Embree's copy and BVH (scene/memory_budget.hpp).
  static std::uint64_t bytes_of(const Shape& s) {
    if (s.exact) return kBytesPerExactShape;
    std::uint64_t bytes = s.mesh.triangles.size() * kBytesPerTriangle + s.mesh.positions.size() * kBytesPerVertex;
    for (const auto& a : s.mesh.attributes) bytes += a.values.size() * sizeof(float);
    return bytes;
  }

  void charge(const Node& n, std::uint64_t bytes, const std::string& what) {
    try {
      budget_.charge(bytes, MemoryBudget::Part::geometry, what);
    } catch (const InputError& e) {
      n.fail(e.what());
    }
  }
  void charge(const Node& n, const Shape& s) { charge(n, bytes_of(s), "shape '" + terminal_safe(s.id) + "'"); }

  void count_triangles(const Node& n, std::size_t added) {
    triangles_ += added;
    if (triangles_ > kMaxSceneTriangles)
      n.fail("the scene reaches " + std::to_string(triangles_) + " triangles with this shape, more than the " +
             std::to_string(kMaxSceneTriangles) + " it may hold (instances count each copy)");
  }

  // Mitsuba's `shapegroup`: shapes that are not rendered themselves, only through `instance`s of the group.
  void shapegroup(const Node& n) {
    register_id(n, "shapegroup");
    if (!n.has("id")) n.fail("a shapegroup needs an id (instances refer to it)");
    const Props p(n);
    std::vector<Shape> group;
    for (const Node& o : p.objects) {
      if (o.tag() != "shape") o.fail("a shapegroup holds shapes only");
      const std::string type = o.attr_or("type", "");
      if (type == "shapegroup" || type == "instance") o.fail("shapegroups do not nest (as in Mitsuba)");
      group.push_back(build_shape(o));
      if (group.back().is_emitter()) o.fail("a shape in a shapegroup cannot emit (as in Mitsuba)");
      count_triangles(o, group.back().primitive_count());
      charge(o, group.back());
    }
    p.check_all_used();
    if (group.empty()) n.fail("the shapegroup holds no shape");
    groups_[n.attr("id")] = std::move(group);
  }

  // Mitsuba's `instance`: a copy of a shapegroup's shapes under its own to_world.
  void instance(const Node& n) {
    register_id(n, "shape");
    const Props p(n);
    const Node* ref = nullptr;
    for (const Node& o : p.objects) {
      if (o.tag() != "ref" || ref) o.fail("an instance refers to one shapegroup");
      ref = &o;
    }
    for (const auto& [name, o] : p.named)
      if (o.tag() == "ref") {
        if (ref) o.fail("an instance refers to one shapegroup");
        ref = p.find(name);
      }
    if (!ref) n.fail("an instance needs a <ref> to a shapegroup");
    build_declared(ref->attr("id"));
    const auto group = groups_.find(ref->attr("id"));
    if (group == groups_.end()) ref->fail("'" + ref->attr("id") + "' is no shapegroup");
    const glm::mat4 to_world = p.transform("to_world");
    check_to_world(n, to_world);
    p.check_all_used();
    const std::string id = n.attr_or("id", "instance " + std::to_string(scene_.shapes.size()));
    std::size_t copies = 0;
    std::uint64_t bytes = 0;
    for (const Shape& member : group->second) {
      copies += member.primitive_count();
      bytes += bytes_of(member);
    }
    count_triangles(n, copies);
    charge(n, bytes, "instance '" + terminal_safe(id) + "'");
    for (const Shape& member : group->second) {
      Shape s = member;
      s.id = id + "/" + member.id;
      place(n, s, to_world);
      // A sphere this copy stretched into an ellipsoid, and so tessellated.
      count_triangles(n, s.primitive_count() - member.primitive_count());
      charge(n, bytes_of(s) - bytes_of(member), "shape '" + terminal_safe(s.id) + "'");
      scene_.shapes.push_back(std::move(s));
    }
  }

  // Moves shape `s` by `to_world` and validates it. An exact shape stays exact where to_world keeps it one; a sphere
  // stretched into an ellipsoid or a cylinder into an elliptic tube is tessellated (Mitsuba refuses the one and
  // mis-sizes the other; a tessellation shows what was asked for).
  void place(const Node& n, Shape& s, const glm::mat4& to_world) {
    if (s.exact) {
      if (const auto moved = ExactShape::from(s.exact->kind, to_world * s.exact->to_world(), s.exact->flip)) {
        s.exact = moved;
        Vec3 lo, hi;
        moved->bounds(lo, hi);
        if (glm::any(glm::greaterThan(glm::max(glm::abs(lo), glm::abs(hi)), Vec3(kMaxCoordinate))))
          n.fail("the shape reaches beyond ±1e12, farther than single-precision ray tracing can resolve");
        return;
      }
      if (s.exact->kind == ExactShape::Kind::disk) n.fail("the disk's to_world is singular (a zero scale?)");
      s.mesh = tessellate(s.exact->kind);
      s.mesh.transform(s.exact->to_world());
      if (s.exact->flip) s.mesh.flip();
      s.exact.reset();
    }
    s.mesh.transform(to_world);
    s.mesh.validate(n.where());
  }

  static void check_to_world(const Node& n, const glm::mat4& to_world) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(to_world[c][r])) n.fail("the to_world transform is not finite (it overflows)");
    // A singular to_world (a zero scale) flattens the mesh and leaves its normals undefined.
    if (!(std::fabs(glm::determinant(glm::mat3(to_world))) > 0))
      n.fail("the to_world transform is singular (a zero scale?)");
  }

  Shape build_shape(const Node& n) {
    register_id(n, "shape");
    const Props p(n);
    const std::string type = p.type();
    if (const char* why = loader::refused_plugin("shape", type)) n.fail(why);
    const auto reader = loader::shape_reader(type);
    if (!reader) n.fail("unsupported shape type '" + type + "'");
    Shape s;
    s.id = n.attr_or("id", "shape " + std::to_string(scene_.shapes.size()));
    loader::ShapePlugin made;
    try {
      made = reader(*this, p);
    } catch (const InputError& e) {
      if (std::string(e.what()).starts_with(n.where())) throw;
      n.fail(e.what());  // a mesh file's own message, prefixed with the element that named it
    }
    const glm::mat4 to_world = p.transform("to_world") * made.to_world;
    check_to_world(n, to_world);
    const bool flip = p.boolean("flip_normals", false);
    if (made.exact) {
      s.exact = ExactShape::from(*made.exact, glm::mat4(1.0f), flip);
    } else {
      s.mesh = std::move(made.mesh);
      if (p.boolean("face_normals", false)) s.mesh.normals.clear();
      if (flip) s.mesh.flip();
    }
    place(n, s, to_world);

    std::shared_ptr<const Bsdf> b;
    auto set_bsdf = [&](const Node& o, std::shared_ptr<const Bsdf> nested) {
      if (b) o.fail("a shape has one BSDF");
      b = std::move(nested);
    };
    auto set_emitter = [&](const Node& o, const Texture& radiance) {
      if (s.is_emitter() || s.radiance_texture) o.fail("a shape has one emitter");
      s.radiance = radiance.mean();
      if (!radiance.is_constant()) s.radiance_texture = radiance;
    };
    auto reference = [&](const Node& o) {
      const std::string id = o.attr("id");
      build_declared(id);
      if (const auto it = area_emitters_.find(id); it != area_emitters_.end())
        set_emitter(o, it->second);
      else
        set_bsdf(o, bsdf_reference(o));
    };
    for (const Node& o : p.objects) {
      const std::string t = o.tag();
      if (t == "bsdf") {
        set_bsdf(o, bsdf(o));
      } else if (t == "ref") {
        reference(o);
      } else if (t == "emitter") {
        auto e = emitter_plugin(o);
        if (e.area)
          set_emitter(o, *e.area);
        else  // Mitsuba renders a point, spot, … light nested in a shape as one declared beside it
          add_light(o, std::move(e));
      } else {
        o.fail("unexpected inside a shape");
      }
    }
    // Named references (<ref name="bsdf" id=".."/>): Mitsuba finds a shape's objects by their kind, not their name.
    for (const auto& [name, o] : p.named)
      if (o.tag() == "ref") reference(*p.find(name));
    p.check_all_used();
    // Mitsuba documents that an sdfgrid cannot emit: it loads one but samples no point on it (its surface area is
    // 0), so light sampling never finds it. Our mesh could emit, but would render a different image: refused.
    if (s.is_emitter() && type == "sdfgrid")
      n.fail("an sdfgrid cannot be an area emitter (Mitsuba samples no point on it)");
    // An emitter that does not reflect: Mitsuba adds its emission where a ray meets it and lets the ray go on
    // straight (its null BSDF's sample), while shadow rays stop there. A sheet of IOR 1 does exactly that, which
    // the geometry's alpha test (a null BSDF's surface vanishes for every ray, its emission with it) would not.
    if (s.is_emitter() && b && dynamic_cast<const NullBsdf*>(b.get()))
      b = std::make_shared<Dielectric>(Dielectric::Kind::thin, 1.0f, Texture(Rgb(1.0f)), Texture(Rgb(1.0f)),
                                       std::nullopt);
    s.material = material_index(b ? b : default_bsdf(s.is_emitter()));
    AttributeUses uses = b ? bsdf_uses_[b.get()] : AttributeUses{};
    if (s.radiance_texture) record_use(*s.radiance_texture, uses);
    keep_attributes(n, s, uses);
    return s;
  }

  // Mitsuba evaluates a mesh_attribute texture on the shape a ray hits, and fails mid-render where the attribute
  // is missing; here every attribute the shape's material or emitter reads must be on its mesh (with 1 or 3
  // channels, finite) when the scene is read. Attributes nothing reads are dropped.
  static void keep_attributes(const Node& n, Shape& s, const AttributeUses& uses) {
    std::vector<MeshAttribute> kept;
    for (const auto& [name, use] : uses) {
      const MeshAttribute* a = s.mesh.attribute(name);
      const std::string what = "mesh_attribute texture '" + use.texture + "' reads attribute '" + name + "'";
      if (!a) {
        std::string has;
        for (const auto& other : s.mesh.attributes) has += (has.empty() ? "" : ", ") + other.name;
        n.fail(what + ", which shape '" + s.id + "' does not have (" +
               (has.empty() ? "it has no attributes" : "it has " + has) + ")");
      }
      if (a->channels != 1 && a->channels != 3)
        n.fail(what + " of shape '" + s.id + "', which has " + std::to_string(a->channels) +
               " channels: only 1 or 3 can be evaluated (as in Mitsuba)");
      if (a->channels != 1 && !use.as_number.empty())
        n.fail(what + " of shape '" + s.id + "' as the number '" + use.as_number + "', but it has " +
               std::to_string(a->channels) + " channels: a number reads a 1-channel attribute (as in Mitsuba)");
      for (const float v : a->values)
        if (!std::isfinite(v)) n.fail(what + " of shape '" + s.id + "', which holds a non-finite value");
      kept.push_back(*a);
    }
    s.mesh.attributes = std::move(kept);
  }

  // ---- emitters -------------------------------------------------------------------------------------------------
  loader::EmitterPlugin emitter_plugin(const Node& n) {
    const Props p(n);
    const std::string type = p.type();
    if (const char* why = loader::refused_plugin("emitter", type)) n.fail(why);
    const auto reader = loader::emitter_reader(type);
    if (!reader) n.fail("unsupported emitter type '" + type + "'");
    AttributeUses uses;
    auto e = gathering_uses(uses, [&] { return reader(*this, p); });
    if (!e.area && !uses.empty())
      n.fail("mesh_attribute texture '" + uses.begin()->second.texture +
             "' on an emitter that is no shape's: only shapes have mesh attributes");
    // Every Mitsuba emitter takes a share of the light samples; clradiosity chooses its own.
    p.ignore({"sampling_weight"});
    p.check_all_used();
    return e;
  }

  void emitter(const Node& n) {
    register_id(n, "emitter");
    auto e = emitter_plugin(n);
    if (e.area) {
      // Mitsuba lets an area emitter be declared once and attached to shapes by <ref>.
      if (!n.has("id")) n.fail("an area emitter must be nested in a shape, or have an id a shape refers to");
      area_emitters_[n.attr("id")] = *e.area;
    } else {
      add_light(n, std::move(e));
    }
  }

  // An emitter that belongs to no shape: the environment or a delta light.
  void add_light(const Node& n, loader::EmitterPlugin&& e) {
    if (e.environment) {
      if (scene_.environment) n.fail("a scene has at most one environment emitter");
      scene_.environment = std::move(e.environment);
    } else if (e.delta) {
      scene_.delta_lights.push_back(std::move(*e.delta));
    }
  }

  // ---- sensor ---------------------------------------------------------------------------------------------------
  void sensor(const Node& n) {
    register_id(n, "sensor");
    const Props p(n);
    const auto reader = loader::sensor_reader(p.type());
    if (!reader) n.fail("unsupported sensor type '" + p.type() + "' (perspective, thinlens, orthographic)");
    // Every sensor is read and checked, in order (Mitsuba's scene.sensors()); the chosen one (--sensor) is the
    // scene's camera.
    Camera c;
    std::optional<int> sample_count;
    reader(*this, p, c);
    p.check_all_used();
    for (const Node& o : p.objects) {
      if (o.tag() == "sampler") {
        // Read only for `reference`'s default spp: a count this loader cannot read (an undefined $spp, as the
        // Mitsuba docs' scenes have) leaves the scene without one instead of refusing a scene that renders.
        try {
          if (const Props sampler(o); sampler.has("sample_count")) sample_count = sampler.integer("sample_count", 0);
        } catch (const InputError&) {
          sample_count.reset();
        }
        continue;
      }
      if (o.tag() == "film") loader::read_film(Props(o), c);
    }
    if (scene_.sensor_count++ == sensor_) {
      scene_.camera = c;
      scene_.sample_count = sample_count;
      scene_.has_sensor = true;
    }
  }

  std::vector<std::unique_ptr<xml::Source>> sources_;
  xml::Parameters params_;
  std::map<std::string, std::string> given_, defaults_;  // the caller's parameters; the files' <default>s
  std::filesystem::path scene_folder_;
  std::vector<std::filesystem::path> search_folders_;
  std::set<std::filesystem::path> including_;
  std::map<std::string, Node> declared_;    // top-level plugins with an id, by id
  std::set<const void*> built_;             // top-level plugins with an id already built
  std::map<std::string, std::string> ids_;  // id → kind of element
  std::map<std::string, std::shared_ptr<const Bsdf>> bsdfs_;
  std::map<std::string, Texture> textures_;
  std::vector<AttributeUses> attribute_scopes_;  // the materials and emitters being built, innermost last
  int depth_ = 0;                                // the loader's recursion (Deeper)
  std::size_t triangles_ = 0;                    // in the scene's shapes, groups and instances so far
  MemoryBudget budget_;                          // what they and the images cost
  // How deep a BSDF's nesting goes and how many BSDFs one evaluation visits (itself included).
  struct BsdfExtent {
    int depth = 1;
    std::size_t visits = 1;
  };
  std::map<const Bsdf*, BsdfExtent> extents_;
  std::vector<std::vector<std::shared_ptr<const Bsdf>>> nesting_;  // the BSDFs nested by those being built
  std::map<const Bsdf*, AttributeUses> bsdf_uses_;                 // what each material's textures read of a mesh
  std::map<std::string, Texture> area_emitters_;
  std::map<std::string, std::vector<Shape>> groups_;  // shapegroups by id
  std::map<std::tuple<std::string, bool, float, Bitmap::Storage>, std::shared_ptr<const Bitmap>> bitmaps_;
  std::map<const Bsdf*, int> material_ids_;
  std::shared_ptr<const Bsdf> default_bsdfs_[2];
  int sensor_ = 0;  // the sensor that becomes the scene's camera
  std::set<std::filesystem::path> recorded_;
  Scene scene_;
};

}  // namespace

Scene load_scene(const std::filesystem::path& path, const std::map<std::string, std::string>& parameters, int sensor) {
  return Loader(parameters, sensor).load(path);
}

void require_emitter(const Scene& scene, const std::filesystem::path& path) {
  if (scene.environment || !scene.delta_lights.empty()) return;
  // A shape whose triangles are all degenerate is a valid part of a scene (it is never hit), but no light.
  for (const auto& s : scene.shapes)
    if (s.is_emitter() && s.area() > 0) return;
  throw InputError(path.string() +
                   ": the scene has no emitter (an area emitter on a shape of non-zero area, an environment or "
                   "a point, spot, directional or projector light): every radiance would be zero");
}

void require_sensor(const Scene& scene, const std::filesystem::path& path) {
  if (!scene.has_sensor) throw InputError(path.string() + ": the scene has no <sensor> to render from");
  scene.camera.validate(path.string() + ": <sensor>");
}

}  // namespace clr::scene
