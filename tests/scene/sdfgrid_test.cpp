// Mitsuba's sdfgrid: the .vol reader, the mesh of the zero level set of a grid's trilinear interpolant (area,
// volume, normals and closure against analytic shapes, distance to the interpolant's surface) and the plugin.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>

#include "common/error.hpp"
#include "scene/scene.hpp"
#include "scene/scene_files.hpp"
#include "scene/sdf_grid.hpp"
#include "scene/shapes/sdf_interpolant.hpp"

namespace clr::test {
namespace {

using scene::Vec3;

class SdfGrid : public SceneFiles {};

template <typename T>
void put(std::string& s, T v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// A .vol file; `version` and `encoding` as given, the bounding box zero.
std::string vol(const glm::ivec3& size, int channels, const std::vector<float>& values, int encoding = 1,
                char version = 3) {
  std::string f = std::string("VOL") + version;
  for (const std::int32_t v : {encoding, size.x, size.y, size.z, channels}) put(f, v);
  for (int i = 0; i < 6; ++i) put(f, 0.0f);
  for (const float v : values) put(f, v);
  return f;
}

// An n³ grid of `sdf` at the samples' object-space positions.
scene::VolumeGrid sampled(int n, const std::function<float(const Vec3&)>& sdf) {
  scene::VolumeGrid g;
  g.size = glm::ivec3(n);
  g.channels = 1;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) g.values.push_back(sdf(Vec3(x, y, z) / float(n - 1)));
  return g;
}

double enclosed_volume(const scene::Mesh& m) {  // the divergence theorem, exact for a closed outward mesh
  double v = 0;
  for (const auto& t : m.triangles)
    v += double(glm::dot(m.positions[t.x], glm::cross(m.positions[t.y], m.positions[t.z]))) / 6.0;
  return v;
}

// Every edge in exactly two triangles, once in each direction: closed and consistently wound.
void expect_closed(const scene::Mesh& m) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : m.triangles)
    for (int i = 0; i < 3; ++i) ++directed[{t[i], t[(i + 1) % 3]}];
  for (const auto& [e, count] : directed) {
    ASSERT_EQ(count, 1) << "edge " << e.first << "-" << e.second << " repeated in one direction";
    ASSERT_EQ(directed.count({e.second, e.first}), 1u) << "edge " << e.first << "-" << e.second << " is a border";
  }
}

// The largest distance, in grid cells, from a triangle's centroid to the interpolant's zero set (to first order:
// |f| / |∇f|, both in grid units).
double centroid_error_cells(const scene::VolumeGrid& g, const scene::Mesh& m) {
  const scene::SdfInterpolant f(g);
  double worst = 0;
  for (const auto& t : m.triangles) {
    const Vec3 c = (m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0f * f.scale();
    const Vec3 grad = f.gradient(c, f.cell_of(c)) / f.scale();
    if (glm::length(grad) > 0) worst = std::max(worst, double(std::fabs(f.value(c)) / glm::length(grad)));
  }
  return worst;
}

TEST_F(SdfGrid, VolReadsValuesXFastest) {
  std::vector<float> values(3 * 2 * 2);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = float(i);
  const auto g = scene::load_vol(write("g.vol", vol({3, 2, 2}, 1, values)));
  EXPECT_EQ(g.size, glm::ivec3(3, 2, 2));
  EXPECT_EQ(g.channels, 1);
  EXPECT_EQ(g.at(2, 0, 0), 2.0f);
  EXPECT_EQ(g.at(0, 1, 0), 3.0f);
  EXPECT_EQ(g.at(1, 1, 1), 10.0f);
}

TEST_F(SdfGrid, VolRefusesBadFilesByName) {
  const std::vector<float> eight(8, 1.0f);
  std::vector<float> nan = eight;
  nan[5] = std::numeric_limits<float>::quiet_NaN();
  const std::string good = vol({2, 2, 2}, 1, eight);
  const std::pair<std::string, std::string> bad[] = {
      {"XOL" + good.substr(3), "no 'VOL' magic"},
      {vol({2, 2, 2}, 1, eight, 1, 2), "version 2"},
      {vol({2, 2, 2}, 1, eight, 3), "encoding 3"},
      {vol({0, 2, 2}, 1, {}), "resolution 0 along x"},
      {vol({2, 1, 2}, 1, eight), "resolution 1 along y"},
      {vol({2, 2, 100000}, 1, eight), "resolution 100000 along z"},
      {vol({2, 2, 2}, 0, eight), "0 channels"},
      {good.substr(0, 30), "truncated .vol header"},
      {good.substr(0, good.size() - 1), "announces 8 values, more than the file's 31 bytes"},
      {vol({2, 2, 2}, 1, nan), "value 5 is not finite"},
  };
  for (const auto& [bytes, fragment] : bad) {
    const auto path = write("bad.vol", bytes);
    try {
      scene::load_vol(path);
      ADD_FAILURE() << "accepted; expected: " << fragment;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
  }
}

// The relative shrinkage of a convex shape of radius r (in cells) that the grid itself causes, Mitsuba's surface as
// much as ours: between samples the interpolant of a distance overestimates it by about (1 cell)² / 8r.
double grid_shrinkage(double r_cells) { return 1.0 / (8 * r_cells * r_cells); }

// A sphere's distance sampled on a 48³ grid: the mesh is closed and outward, its area and volume are the sphere's
// to within the grid's own interpolation error (twice and three times the radius' error, with the chords' a little
// more), and both normal modes point along the radius.
TEST_F(SdfGrid, SphereMeshIsClosedWithTheSpheresAreaVolumeAndNormals) {
  const Vec3 centre(0.5f, 0.47f, 0.52f);
  const float r = 0.35f;
  const auto g = sampled(48, [&](const Vec3& p) { return glm::length(p - centre) - r; });
  for (const auto mode : {scene::SdfNormals::smooth, scene::SdfNormals::analytic}) {
    const auto m = scene::mesh_sdf_grid(g, mode, "sphere");
    expect_closed(m);
    const double area = 4 * M_PI * r * r, volume = 4.0 / 3.0 * M_PI * r * r * r, shrink = grid_shrinkage(r * 47);
    EXPECT_NEAR(m.area(), area, 3 * shrink * area);
    EXPECT_NEAR(enclosed_volume(m), volume, 4.5 * shrink * volume);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    float worst = 1;
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      EXPECT_NEAR(glm::length(m.normals[i]), 1.0f, 1e-5f);
      worst = std::min(worst, glm::dot(m.normals[i], glm::normalize(m.positions[i] - centre)));
    }
    EXPECT_GT(worst, 0.999f);
  }
}

// A surface beyond the triangle budget is refused naming the grid, before its mesh exhausts memory (the default
// budget, 2^24, is too large to reach in a test: the same check with a budget of 100).
TEST_F(SdfGrid, SurfaceBeyondTheTriangleBudgetIsRefused) {
  const auto g = sampled(16, [](const Vec3& p) { return glm::length(p - Vec3(0.5f)) - 0.3f; });
  EXPECT_GT(scene::mesh_sdf_grid(g, scene::SdfNormals::smooth, "sphere").triangles.size(), 100u);
  try {
    scene::mesh_sdf_grid(g, scene::SdfNormals::smooth, "sphere.vol", 0, 100);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "sphere.vol: its surface needs more than 100 triangles");
  }
}

// A torus of the corpus scene's proportions (major radius 10 cells, minor 4, on a 40³ grid, distances in cells):
// closed, its area and volume within the grid's error, and every triangle's centroid near the interpolant's
// surface; that distance shrinks with the lattice step squared (the chord error): 0.043, 0.014, 0.0068 and 0.0038
// cell at 1 to 4 splits per cell, the loader's.
TEST_F(SdfGrid, TorusMeshFollowsTheInterpolantsSurface) {
  constexpr float R = 10, r = 4;
  const auto g = sampled(40, [&](const Vec3& p) {
    const Vec3 q = p * 39.0f - Vec3(19.5f);
    return std::hypot(std::hypot(q.x, q.y) - R, q.z) - r;
  });
  double errors[5] = {};
  for (int k = 1; k <= 4; ++k) {
    const auto m = scene::mesh_sdf_grid(g, scene::SdfNormals::smooth, "torus", k);
    expect_closed(m);
    errors[k] = centroid_error_cells(g, m);
    const double cell = 1.0 / 39.0, area = 4 * M_PI * M_PI * R * r * cell * cell,
                 volume = 2 * M_PI * M_PI * R * r * r * cell * cell * cell;
    EXPECT_NEAR(m.area(), area, 3 * grid_shrinkage(r) * area) << "subdivision " << k;
    EXPECT_NEAR(enclosed_volume(m), volume, 4.5 * grid_shrinkage(r) * volume) << "subdivision " << k;
    std::printf("torus, %d splits per cell: %zu triangles, centroids within %.4f cell of the surface\n", k,
                m.triangles.size(), errors[k]);
  }
  EXPECT_LT(errors[4], 0.005);
  EXPECT_LT(errors[4], errors[1] / 8);
}

// A plane is its own trilinear interpolant: the mesh is the unit square at that height, facing +z.
TEST_F(SdfGrid, PlaneIsExact) {
  const auto g = sampled(5, [](const Vec3& p) { return p.z - 0.37f; });
  for (const auto mode : {scene::SdfNormals::smooth, scene::SdfNormals::analytic}) {
    const auto m = scene::mesh_sdf_grid(g, mode, "plane");
    EXPECT_NEAR(m.area(), 1.0, 1e-5);
    for (const auto& p : m.positions) EXPECT_NEAR(p.z, 0.37f, 1e-6f);
    for (const auto& n : m.normals) EXPECT_NEAR(n.z, 1.0f, 1e-6f);
    for (const auto& t : m.triangles)
      EXPECT_GT(glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]).z, 0.0f);
  }
}

TEST_F(SdfGrid, PluginMeshesInTheUnitCubeUnderToWorld) {
  const auto g = sampled(24, [](const Vec3& p) { return glm::length(p - Vec3(0.5f)) - 0.25f; });
  write("ball.vol", vol(g.size, 1, g.values));
  const auto s = scene::load_scene(scene(R"(
    <shape type="sdfgrid"><string name="filename" value="ball.vol"/></shape>
    <shape type="sdfgrid"><string name="filename" value="ball.vol"/><string name="normals" value="analytic"/>
      <transform name="to_world"><scale value="4"/></transform></shape>)"));
  const double area = 4 * M_PI * 0.25 * 0.25, shrink = grid_shrinkage(0.25 * 23);
  EXPECT_NEAR(s.shapes[0].mesh.area(), area, 3 * shrink * area);
  EXPECT_NEAR(s.shapes[1].mesh.area(), 16 * area, 16 * 3 * shrink * area);
  // Mitsuba's sdfgrid has no texture coordinates: uv (0, 0), not a mesh's barycentric default.
  ASSERT_EQ(s.shapes[0].mesh.uvs.size(), s.shapes[0].mesh.positions.size());
  for (const auto& uv : s.shapes[0].mesh.uvs) EXPECT_EQ(uv, scene::Vec2(0.0f));
  // Pointwise up to three times the mean shrinkage: at a cell's centre all three axes interpolate.
  for (const auto& p : s.shapes[1].mesh.positions) EXPECT_NEAR(glm::length(p - Vec3(2.0f)), 1.0f, 3 * shrink);
}

TEST_F(SdfGrid, PluginRefusesByName) {
  const std::vector<float> crossing = {-1, 1, -1, 1, -1, 1, -1, 1};
  write("rgb.vol", vol({2, 2, 2}, 3, std::vector<float>(24, -1.0f)));
  write("outside.vol", vol({2, 2, 2}, 1, std::vector<float>(8, 0.5f)));
  write("plane.vol", vol({2, 2, 2}, 1, crossing));
  const std::pair<std::string, std::string> bad[] = {
      {R"(<string name="filename" value="rgb.vol"/>)", "3 channels, but an SDF grid has 1"},
      {R"(<string name="filename" value="outside.vol"/>)", "no zero crossing"},
      {R"(<string name="filename" value="plane.vol"/><string name="normals" value="flat"/>)", "unknown normals 'flat'"},
      {R"(<string name="filename" value="missing.vol"/>)", "missing.vol"},
      {R"(<string name="filename" value="plane.vol"/><emitter type="area"/>)", "cannot be an area emitter"},
  };
  for (const auto& [props, fragment] : bad) {
    try {
      scene::load_scene(scene("<shape type=\"sdfgrid\">" + props + "</shape>"));
      ADD_FAILURE() << "accepted; expected: " << fragment;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace clr::test
