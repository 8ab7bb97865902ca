// Camera paths: keyframes interpolated as documented (the ends exact, positions linear or Catmull-Rom, orientations
// slerped), orbits that keep the sensor's distance, height and view, and malformed paths refused by name.
#include "scene/sensors/camera_path.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "common/error.hpp"

namespace clr::scene {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class CameraPath : public ::testing::Test {
 protected:
  void SetUp() override {
    sensor.to_world = *look_at({0, 1, 6.8f}, {0, 1, 0}, {0, 1, 0});
    sensor.fov_degrees = 40;
  }
  void TearDown() override { fs::remove(file); }
  std::vector<Camera> read(const std::string& json) {
    std::ofstream(file) << json;
    return read_camera_path(file, sensor);
  }
  static Vec3 origin(const Camera& c) { return Vec3(c.to_world[3]); }
  static Vec3 view(const Camera& c) { return glm::normalize(Vec3(c.to_world[2])); }
  const fs::path file = fs::temp_directory_path() / ("clr_camera_path" + std::to_string(::getpid()) + ".json");
  Camera sensor;
};

void expect_near(const Vec3& a, const Vec3& b, float tolerance, const std::string& what) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], tolerance) << what << " [" << i << "]";
}

TEST_F(CameraPath, EndsAreTheKeyframesAndTheMiddleIsInterpolated) {
  const auto cams = read(R"({"frames": 5, "interpolation": "linear", "keyframes": [
      {"origin": [0, 1, 6], "target": [0, 1, 0], "fov": 30},
      {"origin": [4, 1, 6], "target": [4, 1, 0], "up": [0, 1, 0], "fov": 50}]})");
  ASSERT_EQ(cams.size(), 5u);
  expect_near(origin(cams[0]), {0, 1, 6}, 1e-5f, "first");
  expect_near(origin(cams[4]), {4, 1, 6}, 1e-5f, "last");
  expect_near(origin(cams[2]), {2, 1, 6}, 1e-5f, "middle, linear");
  EXPECT_FLOAT_EQ(cams[0].fov_degrees, 30);
  EXPECT_FLOAT_EQ(cams[2].fov_degrees, 40);
  for (const auto& c : cams) expect_near(view(c), {0, 0, -1}, 1e-5f, "the same orientation throughout");
  EXPECT_EQ(cams[0].width, sensor.width) << "the sensor's film";
}

TEST_F(CameraPath, OrientationsAreSlerpedAndPositionsSmoothThroughKeyframes) {
  // A quarter turn: the middle frame looks along the diagonal, at unit length (a slerp, not a lerp of vectors).
  auto cams = read(R"({"frames": 3, "keyframes": [
      {"origin": [0, 0, 0], "target": [0, 0, -1]}, {"origin": [0, 0, 0], "target": [1, 0, 0]}]})");
  expect_near(view(cams[1]), glm::normalize(Vec3(1, 0, -1)), 1e-5f, "halfway");
  EXPECT_NEAR(glm::length(Vec3(cams[1].to_world[0])), 1.0f, 1e-5f);
  // Smooth: the path passes through every keyframe; between them it differs from the straight segments.
  cams = read(R"({"frames": 9, "keyframes": [
      {"origin": [0, 0, 0], "target": [0, 0, -1]}, {"origin": [1, 0, 0], "target": [1, 0, -1]},
      {"origin": [1, 1, 0], "target": [1, 1, -1]}]})");
  expect_near(origin(cams[4]), {1, 0, 0}, 1e-5f, "the middle keyframe");
  EXPECT_GT(glm::length(origin(cams[6]) - Vec3(1, 0.5f, 0)), 1e-3f) << "a spline, not the straight segment";
  // Mitsuba's to_world (row-major), with its usual mirror of x, is accepted and kept.
  cams = read(R"({"frames": 2, "keyframes": [{"to_world": [-1,0,0,1, 0,1,0,2, 0,0,1,3, 0,0,0,1], "fov": 45}]})");
  expect_near(origin(cams[1]), {1, 2, 3}, 1e-6f, "to_world's translation");
  EXPECT_LT(glm::determinant(glm::mat3(cams[1].to_world)), 0) << "the mirror is kept";
}

TEST_F(CameraPath, MalformedPathsAreRefusedByName) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"frames": 0, "keyframes": [{"origin": [0,0,0], "target": [0,0,1]}]})", "frames must be"},
      {R"({"frames": 2.5, "keyframes": [{"origin": [0,0,0], "target": [0,0,1]}]})", "frames must be"},
      {R"({"frames": 2, "keyframes": []})", "keyframes must be a non-empty list"},
      {R"({"frames": 2, "keyframes": [{"origin": [0,0,0], "target": [0,0,0]}]})", "keyframes[0]: origin and target"},
      {R"({"frames": 2, "keyframes": [{"origin": [0,0,0], "target": [0,1,0], "up": [0,1,0]}]})", "parallel"},
      {R"({"frames": 2, "keyframes": [{"origin": [0,0,0], "target": [0,0,1], "fov": 180}]})", "fov must be"},
      {R"({"frames": 2, "keyframes": [{"origin": [0,0,1e39], "target": [0,0,1]}]})", "finite"},
      {R"({"frames": 2, "keyframes": [{"origin": [0,0,0], "targte": [0,0,1]}]})", "unknown key 'targte'"},
      {R"({"frames": 2, "interpolation": "cubic", "keyframes": [{"origin": [0,0,0], "target": [0,0,1]}]})",
       "interpolation must be"},
      {R"({"frames": 2, "keyframes": [{"to_world": [1,0.5,0,0, 0,0.8660254,0,0, 0,0,1,0, 0,0,0,1]}]})", "shears"},
      {R"({"frames": 2, "keyframes": [{"to_world": [2,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}]})", "scales"},
      {R"({"frames": 2, "keyframes": [{"to_world": [-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]},
                                      {"to_world": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}]})",
       "mix mirrored"},
      {R"({"frames": 2, "keyframes": [{"origin": [1e13,0,0], "target": [0,0,1]}]})", "frame 0"},
      {"[1, 2", "malformed"},
      // Values of the wrong JSON type: an error naming the file (exit 2), never nlohmann's raw type_error.
      {R"({"frames": 2, "interpolation": 3, "keyframes": [{"origin": [0,0,0], "target": [0,0,1]}]})",
       "interpolation must be smooth or linear, got 3"},
      {R"({"frames": 2, "interpolation": null, "keyframes": [{"origin": [0,0,0], "target": [0,0,1]}]})",
       "interpolation must be"},
      {R"({"frames": "2", "keyframes": [{"origin": [0,0,0], "target": [0,0,1]}]})", "frames must be"},
      {R"({"frames": 2, "keyframes": [{"origin": "here", "target": [0,0,1]}]})", "origin must be 3 numbers"},
      {R"({"frames": 2, "keyframes": [{"origin": [0,0,0], "target": [0,0,1], "up": {"y": 1}}]})", "up must be"},
      {R"({"frames": 2, "keyframes": [{"to_world": "identity"}]})", "to_world must be 16 numbers"},
      {R"({"frames": 2, "keyframes": {"a": 1}})", "keyframes must be a non-empty list"},
      {R"({"frames": 2, "keyframes": [7]})", "keyframes[0] must be an object"}};
  for (const auto& [json, culprit] : cases) {
    try {
      read(json);
      ADD_FAILURE() << json << " was read";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(culprit)) << json;
      EXPECT_THAT(e.what(), HasSubstr(file.string())) << json;
    }
  }
}

TEST_F(CameraPath, AnOrbitKeepsTheSensorsDistanceHeightAndView) {
  const Vec3 centre(0, 1, 0);
  const auto cams = orbit(sensor, centre, 8);
  ASSERT_EQ(cams.size(), 8u);
  EXPECT_EQ(cams[0].to_world, sensor.to_world) << "frame 0 is the sensor's view";
  for (const auto& c : cams) {
    const Vec3 o = origin(c) - centre;
    EXPECT_NEAR(o.y, 0.0f, 1e-5f) << "height";
    EXPECT_NEAR(glm::length(o), 6.8f, 1e-4f) << "distance";
    EXPECT_NEAR(glm::dot(view(c), -glm::normalize(o)), 1.0f, 1e-5f) << "still looking at the centre";
  }
  expect_near(origin(cams[4]), {0, 1, -6.8f}, 1e-4f, "half way round");
  expect_near(origin(cams[2]), {6.8f, 1, 0}, 1e-4f, "a quarter turn (counter-clockwise about +y)");
}

}  // namespace
}  // namespace clr::scene
