// The renderer with a known radiance field: environment lookups, delta chains and the query rows it builds.
#include "radiosity/renderer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "reference/path_tracer.hpp"
#include "scene/scene.hpp"

namespace clr::radiosity {
namespace {

const std::filesystem::path kScenes = std::filesystem::path(CLR_SOURCE_DIR) / "scenes";

TEST(Renderer, FollowsDeltaChainsAndSeesTheEnvironment) {
  const auto scene = scene::load_scene(kScenes / "mirror-under-sky.xml");
  const geometry::Geometry geometry(scene);
  const float field[3] = {0.25f, 0.5f, 0.75f};
  std::size_t queried = 0;
  const RadianceQuery query = [&](std::span<const float> rows, std::span<float> rgb) {
    for (std::size_t r = 0; r < rows.size() / nn::kRawInputs; ++r) {
      const float* row = &rows[r * nn::kRawInputs];
      // Every query lands on the panel behind the camera (z = 6, normal −z), looking back down at the mirror.
      EXPECT_NEAR(row[nn::raw::kPosition + 2], 6.0f, 1e-4f);
      EXPECT_NEAR(row[nn::raw::kNormal + 2], -1.0f, 1e-5f);
      EXPECT_LT(row[nn::raw::kDirection + 2], -0.9f);
      EXPECT_NEAR(row[nn::raw::kAlbedo], 0.2f, 1e-6f);
      for (int c = 0; c < 3; ++c) rgb[3 * r + c] = field[c];
    }
    queried += rows.size() / nn::kRawInputs;
  };
  RenderSettings settings;
  settings.spp = 1;
  const auto img = render(geometry, query, settings);
  ASSERT_EQ(img.width, 24);
  std::size_t sky = 0, mirror = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const float* p = img.pixel(x, y);
      if (p[0] == 0.5f && p[1] == 0.5f && p[2] == 0.5f) {
        ++sky;
      } else {
        // Mirror (delta, reflectance 0.5) → panel: no emission there, so 0.5 × the field.
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[c], 0.5f * field[c], 1e-6f) << x << "," << y;
        ++mirror;
      }
    }
  EXPECT_GT(sky, 100u);
  EXPECT_GT(mirror, 100u);
  EXPECT_EQ(queried, mirror);
}

// A film of one aspect rendered at another: the renderer must take the same view as the path tracer (the film's
// width and height replaced, the field of view held along fov_axis), not squeeze the film's frame into the image.
// The query returns the hit position, so the image is a map of where each pixel looks; it must match rays cast
// through the pixel centres with the reference's camera model.
TEST(Renderer, AnotherAspectTakesThePathTracersView) {
  auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
  scene.camera.width = 64;  // a 16:9 film …
  scene.camera.height = 36;
  const geometry::Geometry geometry(scene);
  const RadianceQuery position = [](std::span<const float> rows, std::span<float> rgb) {
    for (std::size_t r = 0; r < rows.size() / nn::kRawInputs; ++r)
      for (int c = 0; c < 3; ++c) rgb[3 * r + c] = rows[r * nn::kRawInputs + nn::raw::kPosition + std::size_t(c)];
  };
  RenderSettings settings;  // … rendered square
  settings.width = settings.height = 24;
  settings.spp = 64;
  const auto img = render(geometry, position, settings);
  const scene::Camera camera = scene.camera.resized(24, 24);
  std::vector<double> errors;
  for (int y = 2; y < 22; y += 4)
    for (int x = 2; x < 22; x += 4) {
      const auto cr = camera.ray(float(x) + 0.5f, float(y) + 0.5f);
      const auto hit = geometry.intersect({cr.origin, cr.tnear, cr.direction});
      ASSERT_TRUE(hit.valid());
      const Vec3 expected = geometry.surface(hit).position;
      const float* p = img.pixel(x, y);
      errors.push_back(glm::length(Vec3(p[0], p[1], p[2]) - expected));
    }
  std::sort(errors.begin(), errors.end());
  Vec3 lo(1e30f), hi(-1e30f);
  for (const auto& shape : scene.shapes)
    for (const Vec3& v : shape.mesh.positions) lo = glm::min(lo, v), hi = glm::max(hi, v);
  const double size = glm::length(hi - lo);
  // Within a pixel's footprint (a pixel spans ~1/24 of the view); a squeezed film misses by a fifth of the box.
  EXPECT_LT(errors[errors.size() / 2], 0.02 * size);
}

TEST(Renderer, OtherResolutionsCoverTheSameView) {
  const auto scene = scene::load_scene(kScenes / "mirror-under-sky.xml");
  const geometry::Geometry geometry(scene);
  const RadianceQuery one = [](std::span<const float>, std::span<float> rgb) {
    std::fill(rgb.begin(), rgb.end(), 1.0f);
  };
  RenderSettings settings;
  settings.spp = 16;
  settings.width = settings.height = 12;
  const auto small = render(geometry, one, settings);
  settings.width = settings.height = 48;
  const auto large = render(geometry, one, settings);
  // The mirror covers the same fraction of the image at any resolution.
  const auto mean = [](const image::Image& img) {
    double s = 0;
    for (float v : img.rgb) s += v;
    return s / double(img.rgb.size());
  };
  EXPECT_NEAR(mean(small), mean(large), 0.01);
}

// Memory follows rows_per_query, not the image's width × spp (a line of a wide image at a high spp must not be
// one chunk), and where the chunks are cut does not change a single bit of the image.
TEST(Renderer, ChunksOfAnySizeGiveTheSameImage) {
  // A closed enclosure: every camera sample queries the field, so a chunk's queries are its samples.
  const auto scene = scene::load_scene(kScenes / "furnace-enclosure.xml");
  const geometry::Geometry geometry(scene);
  std::size_t largest = 0;
  const RadianceQuery field = [&](std::span<const float> rows, std::span<float> rgb) {
    largest = std::max(largest, rows.size() / nn::kRawInputs);
    for (std::size_t r = 0; r < rows.size() / nn::kRawInputs; ++r)
      for (int c = 0; c < 3; ++c) rgb[3 * r + c] = rows[r * nn::kRawInputs + nn::raw::kPosition + std::size_t(c)];
  };
  RenderSettings settings;
  settings.spp = 3;
  settings.width = 10;
  settings.height = 6;
  const auto whole = render(geometry, field, settings);
  EXPECT_EQ(largest, 10u * 6u * 3u);
  settings.rows_per_query = 7;  // a prime: chunks end mid-pixel and mid-line
  largest = 0;
  const auto pieces = render(geometry, field, settings);
  EXPECT_LE(largest, 7u);
  EXPECT_EQ(pieces.rgb, whole.rgb);
}

// Frames rendered back to back, with chunks of samples that span frames (and cut frames anywhere), are each the
// image a single render of that camera gives: the same sample streams, the same sums.
TEST(Renderer, FramesBackToBackAreTheSingleRendersOfTheirCameras) {
  auto scene = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
  std::vector<scene::Camera> cameras;
  for (const float x : {0.0f, 0.4f, -0.3f}) {
    scene::Camera c = scene.camera;
    c.to_world = *scene::look_at({x, 1.0f, 6.8f}, {0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f});
    cameras.push_back(c);
  }
  const RadianceQuery where = [](std::span<const float> rows, std::span<float> rgb) {
    for (std::size_t r = 0; r < rows.size() / nn::kRawInputs; ++r)
      for (int c = 0; c < 3; ++c) rgb[3 * r + c] = rows[r * nn::kRawInputs + nn::raw::kPosition + std::size_t(c)];
  };
  RenderSettings settings;
  settings.spp = 3;
  for (const std::size_t chunk : {std::size_t(1) << 16, std::size_t(700), std::size_t(768)}) {
    settings.rows_per_query = chunk;  // one frame is 16·16·3 = 768 samples: 700 cuts inside frames
    std::vector<image::Image> frames;
    std::vector<std::size_t> order;
    render_frames(geometry::Geometry(scene), cameras, where, settings, [&](std::size_t i, image::Image&& img) {
      order.push_back(i);
      frames.push_back(std::move(img));
    });
    ASSERT_EQ(order, (std::vector<std::size_t>{0, 1, 2})) << "every frame once, in order";
    for (std::size_t i = 0; i < cameras.size(); ++i) {
      scene::Scene single = scene::load_scene(kScenes / "cornell-box.xml", {{"res", "16"}});
      single.camera = cameras[i];
      const auto alone = render(geometry::Geometry(single), where, settings);
      EXPECT_EQ(frames[i].rgb, alone.rgb) << "frame " << i << ", chunk " << chunk;
    }
    EXPECT_NE(frames[0].rgb, frames[1].rgb) << "the cameras differ";
  }
  // A stop between chunks keeps the frames done and renders no more.
  settings.rows_per_query = 768;
  int calls = 0;
  std::size_t delivered = 0;
  render_frames(
      geometry::Geometry(scene), cameras, where, settings, [&](std::size_t, image::Image&&) { ++delivered; },
      [&] { return ++calls > 2; });
  EXPECT_EQ(delivered, 2u);
}

// The right-hand-side image with the true field: the furnace's radiance Le / (1 − ρ) at every pixel, so its
// scattered part ρ Le / (1 − ρ) returned for every query. The mean of Le + direct + one bounce's emission and field
// must be that radiance: the direct term, the bounce and their MIS weights add up to the whole incident light.
TEST(Renderer, RightHandSideOfTheTrueFieldIsTheRadiance) {
  const float rho = 0.6f, le = 1.0f, radiance = le / (1.0f - rho);
  const auto scene =
      scene::load_scene(kScenes / "furnace-enclosure.xml", {{"rho", std::to_string(rho)}, {"le", std::to_string(le)}});
  const geometry::Geometry geometry(scene);
  const RadianceQuery exact = [&](std::span<const float>, std::span<float> rgb) {
    std::fill(rgb.begin(), rgb.end(), radiance - le);
  };
  RenderSettings settings;
  settings.mode = RenderMode::rhs;
  settings.spp = 256;
  settings.width = settings.height = 8;
  const auto img = render(geometry, exact, settings);
  double sum = 0;
  for (const float v : img.rgb) {
    EXPECT_NEAR(v, radiance, 0.03 * radiance);
    sum += v;
  }
  EXPECT_NEAR(sum / double(img.rgb.size()), radiance, 0.003 * radiance);
}

// With a field of zeros the right-hand-side image is emission plus one bounce: the path tracer's image with paths
// of two segments, on every kind of light training takes by next-event estimation (an area light, a sky with its sun
// taken as a directional light, delta lights). 4 × 4-pixel blocks agree within their noise, measured from 6 seeds a
// side (a point light's 1/r² near the ceiling makes the per-pixel noise heavy-tailed, so no fixed bound would do).
TEST(Renderer, RightHandSideWithoutAFieldIsTheTwoSegmentPathTracer) {
  for (const char* name : {"cornell-box.xml", "sunsky.xml", "delta-lights/point.xml", "delta-lights/spot.xml",
                           "delta-lights/directional.xml"}) {
    SCOPED_TRACE(name);
    const auto scene = scene::load_scene(kScenes / name);
    const geometry::Geometry geometry(scene);
    const RadianceQuery zero = [](std::span<const float>, std::span<float> rgb) {
      std::fill(rgb.begin(), rgb.end(), 0.0f);
    };
    constexpr int kSeeds = 6, kSize = 16, kBlock = 4, kBlocks = (kSize / kBlock) * (kSize / kBlock);
    // Per block: the sum over seeds of the block's sum, and of its square, for each side.
    std::vector<double> sum[2], sum2[2];
    for (int side = 0; side < 2; ++side) {
      sum[side].assign(kBlocks, 0.0);
      sum2[side].assign(kBlocks, 0.0);
    }
    for (int seed = 1; seed <= kSeeds; ++seed) {
      RenderSettings settings;
      settings.mode = RenderMode::rhs;
      settings.spp = 256;
      settings.width = settings.height = kSize;
      settings.seed = std::uint64_t(seed);
      reference::RenderOptions o;
      o.width = o.height = kSize;
      o.spp = 256;
      o.max_depth = 2;
      o.seed = std::uint64_t(seed);
      const image::Image images[2] = {render(geometry, zero, settings), reference::render(geometry, o)};
      for (int side = 0; side < 2; ++side)
        for (int b = 0; b < kBlocks; ++b) {
          double v = 0;
          const int bx = b % (kSize / kBlock) * kBlock, by = b / (kSize / kBlock) * kBlock;
          for (int y = by; y < by + kBlock; ++y)
            for (int x = bx; x < bx + kBlock; ++x)
              for (int c = 0; c < 3; ++c) v += images[side].pixel(x, y)[c];
          sum[side][std::size_t(b)] += v;
          sum2[side][std::size_t(b)] += v * v;
        }
    }
    double total = 0;
    for (std::size_t b = 0; b < kBlocks; ++b) {
      double mean[2], var_of_mean[2];
      for (int side = 0; side < 2; ++side) {
        mean[side] = sum[side][b] / kSeeds;
        var_of_mean[side] = std::max(0.0, sum2[side][b] / kSeeds - mean[side] * mean[side]) / (kSeeds - 1);
      }
      total += mean[1];
      // Five standard errors of the difference, and a floor for blocks both sides render (almost) black.
      EXPECT_NEAR(mean[0], mean[1], 5 * std::sqrt(var_of_mean[0] + var_of_mean[1]) + 1e-4 * (1 + mean[1]))
          << "block " << b;
    }
    EXPECT_GT(total, 0.0);
  }
}

}  // namespace
}  // namespace clr::radiosity
