#include "scene/sensors/camera_path.hpp"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <limits>
#include <string>

#include "common/error.hpp"
#include "common/input_file.hpp"

namespace clr::scene {
namespace {

struct Keyframe {
  Vec3 position;
  glm::quat orientation;  // of the frame's columns (x, y, z), made right-handed
  float fov_degrees;
  bool mirrored;  // the x column was negated to make the frame a rotation (Mitsuba's scale x = -1)
};

Vec3 vec3(const nlohmann::json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) throw InputError(where + " must be 3 numbers");
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!j[std::size_t(i)].is_number()) throw InputError(where + " must be 3 numbers");
    v[i] = j[std::size_t(i)].get<float>();
    if (!std::isfinite(v[i])) throw InputError(where + " must be finite");
  }
  return v;
}

Keyframe keyframe(const nlohmann::json& k, const Camera& sensor, const std::string& where) {
  if (!k.is_object()) throw InputError(where + " must be an object");
  for (const auto& [key, value] : k.items())
    if (key != "origin" && key != "target" && key != "up" && key != "to_world" && key != "fov")
      throw InputError(where + ": unknown key '" + clip(key) + "' (origin, target, up, fov, or to_world, fov)");
  glm::mat4 m;
  if (k.contains("to_world")) {
    if (k.contains("origin") || k.contains("target") || k.contains("up"))
      throw InputError(where + ": give either to_world or origin/target/up");
    const auto& t = k.at("to_world");
    if (!t.is_array() || t.size() != 16) throw InputError(where + ".to_world must be 16 numbers (row-major)");
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) {
        const auto& v = t[std::size_t(4 * r + c)];
        if (!v.is_number() || !std::isfinite(v.get<double>()))
          throw InputError(where + ".to_world must be 16 finite numbers");
        m[c][r] = v.get<float>();
      }
  } else {
    if (!k.contains("origin") || !k.contains("target"))
      throw InputError(where + ": give origin and target (and up, fov), or to_world");
    const Vec3 up = k.contains("up") ? vec3(k.at("up"), where + ".up") : Vec3(sensor.to_world[1]);
    const auto frame = look_at(vec3(k.at("origin"), where + ".origin"), vec3(k.at("target"), where + ".target"), up);
    if (!frame) throw InputError(where + ": origin and target must differ and up must not be parallel to the view");
    m = *frame;
  }
  float fov = sensor.fov_degrees;
  if (k.contains("fov")) {
    if (!k.at("fov").is_number()) throw InputError(where + ".fov must be a number");
    fov = k.at("fov").get<float>();
    if (!(fov > 0 && fov < 180)) throw InputError(where + ".fov must be in (0, 180)");
  }
  // The orientation of the columns without their (uniform) scale; a mirror is kept aside: no rotation holds it.
  glm::mat3 r(m);
  const float scale = glm::length(r[2]);
  if (!(scale > 0) || !std::isfinite(scale)) throw InputError(where + ".to_world has no view direction");
  bool mirrored = glm::determinant(r) < 0;
  if (mirrored) r[0] = -r[0];
  for (int c = 0; c < 3; ++c) {
    if (!(std::abs(glm::length(r[c]) - scale) <= 1e-3f * scale))
      throw InputError(where + ".to_world scales its axes differently: a camera path needs rotations");
    r[c] /= scale;
  }
  if (!(std::abs(glm::dot(r[0], r[1])) < 1e-3f && std::abs(glm::dot(r[1], r[2])) < 1e-3f &&
        std::abs(glm::dot(r[0], r[2])) < 1e-3f))
    throw InputError(where + ".to_world shears: a camera path needs rotations");
  return {Vec3(m[3]), glm::normalize(glm::quat_cast(r)), fov, mirrored};
}

Camera place(const Camera& sensor, const Vec3& position, const glm::quat& q, float fov, bool mirrored) {
  Camera c = sensor;
  glm::mat3 r = glm::mat3_cast(glm::normalize(q));
  if (mirrored) r[0] = -r[0];
  c.to_world = glm::mat4(glm::vec4(r[0], 0), glm::vec4(r[1], 0), glm::vec4(r[2], 0), glm::vec4(position, 1));
  c.fov_degrees = fov;
  return c;
}

// Uniform Catmull-Rom through p1 → p2, with p0 and p3 their outer neighbours.
Vec3 catmull_rom(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3, float t) {
  const float t2 = t * t, t3 = t2 * t;
  return 0.5f * (2.0f * p1 + (p2 - p0) * t + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * t2 +
                 (3.0f * p1 - p0 - 3.0f * p2 + p3) * t3);
}

}  // namespace

// read_camera_path without its net for nlohmann's exceptions.
std::vector<Camera> read_camera_path_checked(const std::filesystem::path& file, const Camera& sensor);

std::vector<Camera> read_camera_path(const std::filesystem::path& file, const Camera& sensor) {
  // Every value's type is checked where it is read; a conversion this misses (nlohmann's type_error) is still the
  // file's fault, and is named as such rather than ending as a raw library exception (exit 1).
  try {
    return read_camera_path_checked(file, sensor);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string() + ": not a camera path (" + clip(e.what(), 200) + ")");
  }
}

std::vector<Camera> read_camera_path_checked(const std::filesystem::path& file, const Camera& sensor) {
  const nlohmann::json j = read_json_file(file, "camera path");
  const std::string name = file.string();
  if (!j.is_object()) throw InputError(name + ": a camera path is a JSON object");
  for (const auto& [key, value] : j.items())
    if (key != "frames" && key != "interpolation" && key != "keyframes")
      throw InputError(name + ": unknown key '" + clip(key) + "' (frames, interpolation, keyframes)");
  if (!j.contains("frames") || !j.at("frames").is_number_integer() || j.at("frames").get<long long>() < 1 ||
      j.at("frames").get<long long>() > 100000)
    throw InputError(name + ": frames must be an integer in 1 – 100000");
  const int frames = j.at("frames").get<int>();
  if (j.contains("interpolation") && !j.at("interpolation").is_string())
    throw InputError(name + ": interpolation must be smooth or linear, got " + clip(j.at("interpolation").dump()));
  const std::string interpolation = j.value("interpolation", std::string("smooth"));
  if (interpolation != "smooth" && interpolation != "linear")
    throw InputError(name + ": interpolation must be smooth or linear, got '" + clip(interpolation) + "'");
  if (!j.contains("keyframes") || !j.at("keyframes").is_array() || j.at("keyframes").empty())
    throw InputError(name + ": keyframes must be a non-empty list");
  std::vector<Keyframe> keys;
  for (std::size_t i = 0; i < j.at("keyframes").size(); ++i)
    keys.push_back(keyframe(j.at("keyframes")[i], sensor, name + ": keyframes[" + std::to_string(i) + "]"));
  for (const auto& k : keys)
    if (k.mirrored != keys.front().mirrored)
      throw InputError(name + ": keyframes mix mirrored and unmirrored to_world matrices");

  std::vector<Camera> cameras;
  const std::size_t K = keys.size();
  for (int i = 0; i < frames; ++i) {
    const float u = frames == 1 ? 0.0f : float(i) / float(frames - 1) * float(K - 1);
    const std::size_t k = std::min(std::size_t(u), K > 1 ? K - 2 : 0);
    const float t = K > 1 ? u - float(k) : 0.0f;
    const Keyframe& a = keys[k];
    const Keyframe& b = keys[std::min(k + 1, K - 1)];
    Vec3 position = glm::mix(a.position, b.position, t);
    if (interpolation == "smooth" && K > 2)
      position = catmull_rom(keys[k == 0 ? 0 : k - 1].position, a.position, b.position,
                             keys[std::min(k + 2, K - 1)].position, t);
    cameras.push_back(place(sensor, position, glm::slerp(a.orientation, b.orientation, t),
                            a.fov_degrees + (b.fov_degrees - a.fov_degrees) * t, a.mirrored));
    cameras.back().validate(name + ": frame " + std::to_string(i));
  }
  return cameras;
}

Vec3 geometry_centre(const std::vector<Shape>& shapes) {
  Vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const auto& shape : shapes) shape.extend_bounds(lo, hi);
  return lo.x <= hi.x ? 0.5f * (lo + hi) : Vec3(0.0f);
}

std::vector<Camera> orbit(const Camera& sensor, const Vec3& centre, int frames) {
  const Vec3 up = glm::normalize(Vec3(sensor.to_world[1]));
  std::vector<Camera> cameras;
  for (int i = 0; i < frames; ++i) {
    const float angle = 2.0f * kPi * float(i) / float(frames);
    const glm::mat4 turn = glm::translate(glm::mat4(1.0f), centre) * glm::rotate(glm::mat4(1.0f), angle, up) *
                           glm::translate(glm::mat4(1.0f), -centre);
    Camera c = sensor;
    c.to_world = turn * sensor.to_world;
    c.validate("--orbit: frame " + std::to_string(i));
    cameras.push_back(c);
  }
  return cameras;
}

}  // namespace clr::scene
