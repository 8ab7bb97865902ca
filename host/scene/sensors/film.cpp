// Mitsuba's film as far as it changes the image: its size and its reconstruction filter. Its pixel format, crop
// and the like change nothing clradiosity renders.
#include <cmath>

#include "common/error.hpp"
#include "image/image.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
namespace {

PixelFilter read_filter(const Props& f) {
  const std::string type = f.type();
  // A filter's size: positive and at most a few pixels (Mitsuba's own are 0.5-3; a wider one only blurs, and its
  // table's bins would grow coarse).
  const auto size = [&](const char* name, float fallback, float most) {
    const float v = f.number(name, fallback);
    if (!(v > 0 && v <= most))
      f.expect(name, {"float", "integer"})
          .fail(std::string(name) + " must lie in (0, " + std::to_string(int(most)) + "]");
    return v;
  };
  PixelFilter filter;
  if (type == "box") {
    filter = PixelFilter(PixelFilter::Type::box, size("radius", 0.5f, 16));
  } else if (type == "tent") {
    filter = PixelFilter(PixelFilter::Type::tent, size("radius", 1.0f, 16));
  } else if (type == "gaussian") {
    filter = PixelFilter(PixelFilter::Type::gaussian, size("stddev", 0.5f, 4));
  } else if (type == "mitchell" || type == "catmullrom") {
    const bool mitchell = type == "mitchell";
    const float b = f.number("B", mitchell ? 1.0f / 3.0f : 0.0f), c = f.number("C", mitchell ? 1.0f / 3.0f : 0.5f);
    if (!std::isfinite(b) || !std::isfinite(c)) f.node.fail("B and C must be finite");
    filter = PixelFilter(mitchell ? PixelFilter::Type::mitchell : PixelFilter::Type::catmullrom, 2.0f, b, c);
  } else if (type == "lanczos") {
    const int lobes = f.integer("lobes", 3);
    if (lobes < 1 || lobes > 16) f.expect("lobes", {"integer"}).fail("lobes must lie in [1, 16]");
    filter = PixelFilter(PixelFilter::Type::lanczos, float(lobes));
  } else {
    f.node.fail("unsupported rfilter type '" + type + "' (box, tent, gaussian, mitchell, catmullrom, lanczos)");
  }
  f.check_all_used();
  return filter;
}

}  // namespace

void read_film(const Props& film, Camera& c) {
  c.width = film.integer("width", 768);
  c.height = film.integer("height", 576);
  try {
    image::check_image_size(c.width, c.height, "film");
  } catch (const InputError& e) {
    film.node.fail(e.what());
  }
  c.filter = PixelFilter();
  for (const Node& o : film.objects)
    if (o.tag() == "rfilter") c.filter = read_filter(Props(o));
}

}  // namespace clr::scene::loader
