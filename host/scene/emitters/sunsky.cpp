// Mitsuba 3's `sunsky` emitter: the Hosek–Wilkie sky and sun (scene/sunsky.hpp), placed by `sun_direction` (world
// space) or by a place and local time, with Mitsuba's defaults (Tokyo, 2010-07-10 15:00).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/terminal_text.hpp"
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
EmitterPlugin read_sunsky(Context&, const Props& p) {
  const glm::mat4 to_world = p.transform("to_world");
  SunSkyParameters s;
  bool timed = false;
  for (const char* key : {"latitude", "longitude", "timezone", "year", "month", "day", "hour", "minute", "second"})
    timed = timed || p.has(key);
  if (p.has("sun_direction")) {
    if (timed) p.node.fail("give either 'sun_direction' or a place and time, not both");
    const Vec3 world = p.vector3("sun_direction", Vec3(0, 0, 1));
    const Vec3 local = glm::inverse(glm::mat3(to_world)) * world;
    if (!(glm::length(local) > 0)) p.expect("sun_direction", {"vector"}).fail("the sun_direction is zero");
    s.sun = glm::normalize(local);
  } else {
    const int month = p.integer("month", 7), day = p.integer("day", 10);
    if (month < 1 || month > 12) p.expect("month", {"integer"}).fail("month must lie in 1..12");
    if (day < 1 || day > 31) p.expect("day", {"integer"}).fail("day must lie in 1..31");
    const float latitude = p.number("latitude", 35.6894f);
    if (!(latitude >= -90 && latitude <= 90)) p.expect("latitude", {"float"}).fail("latitude must lie in [-90, 90]");
    s.sun =
        sun_direction(latitude, p.number("longitude", 139.6917f), p.number("timezone", 9.0f), p.integer("year", 2010),
                      month, day, p.number("hour", 15.0f), p.number("minute", 0.0f), p.number("second", 0.0f));
    if (!std::isfinite(s.sun.x + s.sun.y + s.sun.z)) p.node.fail("the place and time give no sun direction");
  }
  s.turbidity = p.number("turbidity", 3.0f);
  if (!(s.turbidity >= 1 && s.turbidity <= 10)) p.expect("turbidity", {"float"}).fail("turbidity must lie in [1, 10]");
  s.albedo = p.color("albedo", Rgb(0.3f));
  if (!(glm::all(glm::greaterThanEqual(s.albedo, Rgb(0.0f))) && glm::all(glm::lessThanEqual(s.albedo, Rgb(1.0f)))))
    p.expect("albedo", {"float", "rgb", "spectrum"}).fail("albedo must lie in [0, 1]");
  s.sun_scale = p.number("sun_scale", 1.0f);
  require_non_negative(p, "sun_scale", Rgb(s.sun_scale));
  s.sky_scale = p.number("sky_scale", 1.0f);
  require_non_negative(p, "sky_scale", Rgb(s.sky_scale));
  s.sun_aperture_deg = p.number("sun_aperture", s.sun_aperture_deg);
  if (!(s.sun_aperture_deg > 0 && s.sun_aperture_deg < 90))
    p.expect("sun_aperture", {"float"}).fail("sun_aperture must lie in (0, 90) degrees (Mitsuba's range)");
  s.complex_sun = p.boolean("complex_sun", false);
  if (s.sun.z < 0)
    std::fprintf(stderr, "%s: warning: the sun is below the horizon: sky and sun are black (as in Mitsuba)\n",
                 terminal_safe(p.node.where()).c_str());
  SunSky model(s);
  // The sun's power spread over its disc: a disc too small (or a scale too large) leaves a radiance no float holds,
  // and the sun would vanish from the image with its non-finite samples. Bounded well inside float, so that the
  // products of a path (radiance × BSDF / density) stay finite too; so is the sky.
  constexpr float kLargestRadiance = 1e30f;
  const auto representable = [&](const Rgb& radiance) {
    return std::isfinite(radiance.x + radiance.y + radiance.z) &&
           std::max({radiance.x, radiance.y, radiance.z}) <= kLargestRadiance;
  };
  const auto g = [](float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(v));
    return std::string(text);
  };
  if (!representable(model.sun_radiance()))
    p.expect(s.sun_scale > 1 ? "sun_scale" : "sun_aperture", {"float"})
        .fail("sun_scale " + g(s.sun_scale) + " over a sun_aperture of " + g(s.sun_aperture_deg) +
              " degrees gives the sun a radiance beyond 1e30, which a float "
              "render cannot carry: widen the aperture or lower the scale");
  if (!representable(model.sky(Vec3(0, 0, 1))) || !representable(model.sky(s.sun)))
    p.expect("sky_scale", {"float"})
        .fail("sky_scale " + g(s.sky_scale) +
              " gives the sky a radiance beyond 1e30, which a float render cannot carry");
  EmitterPlugin e;
  e.environment = std::make_unique<Environment>(Environment::sunsky(std::move(model), to_world));
  return e;
}
}  // namespace clr::scene::loader
