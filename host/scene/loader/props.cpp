#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/terminal_text.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
namespace {
bool is_value_tag(const std::string& t) {
  return t == "float" || t == "integer" || t == "boolean" || t == "string" || t == "rgb" || t == "srgb" ||
         t == "spectrum" || t == "point" || t == "vector" || t == "transform";
}
bool is_object_tag(const std::string& t) {
  return t == "bsdf" || t == "texture" || t == "emitter" || t == "shape" || t == "sensor" || t == "film" ||
         t == "sampler" || t == "rfilter" || t == "integrator" || t == "ref" || t == "medium" || t == "phase";
}
}  // namespace

Props::Props(const Node& plugin) : node(plugin) {
  for (const Node& c : plugin.children()) {
    const std::string t = c.tag();
    if (t == "medium" || t == "phase" || t == "volume") c.fail(refused_plugin(t, c.attr_or("type", "")));
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

const Node* Props::find(const std::string& name) const {
  const auto it = named.find(name);
  if (it == named.end()) return nullptr;
  used.insert(name);
  return &it->second;
}

// Like Mitsuba 3: a property no reader asked for is a misspelling or a feature this plugin lacks, never silently
// dropped. Mitsuba 0.x only warned about them, and files written for it carry such properties (an old plugin's
// switches): those are warned about on stderr.
void Props::check_all_used() const {
  for (const auto& [name, n] : named) {
    if (used.count(name)) continue;
    if (n.source->version_major >= 2)
      n.fail("unused property '" + name + "' (misspelt, or not supported by this plugin)");
    std::fprintf(stderr, "%s: warning: unused property '%s' ignored, as Mitsuba 0.x did\n",
                 clr::terminal_safe(n.where()).c_str(), clr::terminal_safe(name).c_str());
    used.insert(name);
  }
}

void Props::ignore(std::initializer_list<const char*> names) const {
  for (const char* n : names) (void)find(n);
}

const Node& Props::expect(const std::string& name, std::initializer_list<const char*> tags) const {
  const Node* n = find(name);
  if (!n) node.fail("missing property '" + name + "'");
  for (const char* t : tags)
    if (n->tag() == t) return *n;
  n->fail("property '" + name + "' has the wrong type (expected <" + *tags.begin() + ">)");
}

float Props::number(const std::string& name, float fallback) const {
  return has(name) ? expect(name, {"float", "integer"}).number("value") : fallback;
}

int Props::integer(const std::string& name, int fallback) const {
  if (!has(name)) return fallback;
  const Node& n = expect(name, {"integer"});
  const float v = n.number("value");
  if (v != std::floor(v)) n.fail("expected an integer");
  // Converting a float outside int's range is undefined behaviour, not a large number.
  if (!(std::fabs(v) < 2147483648.0f)) n.fail("integer out of range");
  return int(v);
}

bool Props::boolean(const std::string& name, bool fallback) const {
  if (!has(name)) return fallback;
  const Node& n = expect(name, {"boolean"});
  const std::string v = n.attr("value");
  if (v == "true") return true;
  if (v == "false") return false;
  n.fail("expected true or false, got '" + v + "'");
}

std::string Props::string(const std::string& name, const std::string& fallback) const {
  return has(name) ? expect(name, {"string"}).attr("value") : fallback;
}

Rgb Props::color(const std::string& name, const Rgb& fallback) const {
  return has(name) ? expect(name, {"rgb", "srgb", "spectrum", "float"}).color() : fallback;
}

glm::mat4 Props::transform(const std::string& name) const {
  return has(name) ? expect(name, {"transform"}).transform() : glm::mat4(1.0f);
}

Vec3 Props::vector3(const std::string& name, const Vec3& fallback) const {
  return has(name) ? expect(name, {"point", "vector"}).vector3() : fallback;
}

std::shared_ptr<const Bsdf> single_nested_bsdf(Context& ctx, const Props& p) {
  auto nested = ctx.nested_bsdfs(p);
  if (nested.size() != 1) p.node.fail("expects exactly one nested BSDF");
  return nested.front();
}

void require_non_negative(const Props& p, const std::string& property, const Texture& value) {
  const Rgb lo = value.minimum(), mean = value.mean();
  const auto finite = [](const Rgb& c) { return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z); };
  if (!finite(mean) || !finite(lo))
    p.node.fail(property + " must be non-negative and finite (it overflows to infinity)");
  if (!(lo.x >= 0 && lo.y >= 0 && lo.z >= 0)) {
    char smallest[32];
    std::snprintf(smallest, sizeof smallest, "%g", double(std::min({lo.x, lo.y, lo.z})));
    p.node.fail(property + " must be non-negative and finite" +
                (value.is_constant() ? std::string(" (it is ") : std::string(" (a texel holds ")) + smallest + ")");
  }
}

}  // namespace clr::scene::loader
