// The film's reconstruction filter: Mitsuba 3's filter functions and defaults, the offsets drawn ∝ |f| (χ²), the
// weighted mean converging to ∫ f g / ∫ f (a double-precision twin by quadrature), the loader's <rfilter>, and both
// renderers — the path tracer and the model's — applying it across a sharp edge.
#include "scene/pixel_filter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "geometry/geometry.hpp"
#include "radiosity/renderer.hpp"
#include "reference/path_tracer.hpp"
#include "scene/chi2.hpp"
#include "scene/scene.hpp"
#include "scene/scene_files.hpp"

namespace clr::test {
namespace {

using scene::PixelFilter;
using Type = PixelFilter::Type;

std::vector<PixelFilter> every_filter() {
  return {PixelFilter(Type::box, 0.5f),      PixelFilter(Type::box, 1.5f),
          PixelFilter(Type::tent, 1.0f),     PixelFilter(Type::tent, 2.5f),
          PixelFilter(Type::gaussian, 0.5f), PixelFilter(Type::gaussian, 0.3f),
          PixelFilter(Type::mitchell, 2.0f), PixelFilter(Type::catmullrom, 2.0f, 0.0f, 0.5f),
          PixelFilter(Type::lanczos, 3.0f),  PixelFilter(Type::lanczos, 2.0f)};
}

// ∫ g f over [-r, r], or over [lo, hi] within it (Simpson, double precision).
template <class G>
double integrate(const PixelFilter& f, G g, double lo = -1e30, double hi = 1e30, int n = 1 << 14) {
  lo = std::max(lo, -double(f.radius()));
  hi = std::min(hi, double(f.radius()));
  const double h = (hi - lo) / n;
  double s = 0;
  for (int i = 0; i <= n; ++i) {
    const double x = lo + h * i, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    s += w * g(x) * double(f.eval(float(x)));
  }
  return s * h / 3;
}

TEST(PixelFilter, MatchesMitsubasDefinitions) {
  EXPECT_FLOAT_EQ(PixelFilter(Type::tent, 1.0f).eval(0.25f), 0.75f);
  EXPECT_FLOAT_EQ(PixelFilter(Type::box, 0.5f).eval(0.49f), 1.0f);
  EXPECT_FLOAT_EQ(PixelFilter(Type::box, 0.5f).eval(0.51f), 0.0f);
  // Gaussian: exp(-x²/2σ²) - exp(-r²/2σ²), r = 4σ.
  const PixelFilter g(Type::gaussian, 0.5f);
  EXPECT_FLOAT_EQ(g.radius(), 2.0f);
  EXPECT_NEAR(g.eval(0.5f), std::exp(-0.5) - std::exp(-8.0), 1e-6);
  EXPECT_FLOAT_EQ(g.eval(2.0f), 0.0f);
  // Mitchell–Netravali (B = C = 1/3) at 0 and 1 pixel, Catmull–Rom's zero crossing at 1 pixel, Lanczos' negative lobe.
  EXPECT_NEAR(PixelFilter(Type::mitchell, 2.0f).eval(0.0f), (6 - 2.0 / 3) / 6, 1e-6);
  EXPECT_NEAR(PixelFilter(Type::mitchell, 2.0f).eval(1.0f), 1.0 / 18, 1e-6);
  EXPECT_NEAR(PixelFilter(Type::catmullrom, 2.0f, 0.0f, 0.5f).eval(1.0f), 0.0, 1e-6);
  EXPECT_NEAR(PixelFilter(Type::lanczos, 3.0f).eval(1.5f), -1.0 / (M_PI * M_PI * 2.25 / 3), 1e-6);
  // Mitsuba's film default.
  EXPECT_EQ(PixelFilter().type(), Type::gaussian);
  EXPECT_FLOAT_EQ(PixelFilter().radius(), 2.0f);
}

// Offsets fall ∝ |f|: Pearson's χ² over 41 bins of [-r, r], expected counts from the quadrature.
TEST(PixelFilter, OffsetsFollowTheFilter) {
  for (const PixelFilter& f : every_filter()) {
    SCOPED_TRACE(f.describe());
    constexpr int kBins = 41, kSamples = 400000;
    std::vector<double> count(kBins, 0.0), expected(kBins, 0.0);
    const double r = f.radius();
    const double total = integrate(f, [&](double x) { return f.eval(float(x)) < 0 ? -1.0 : 1.0; });
    for (int b = 0; b < kBins; ++b) {
      const double lo = -r + 2 * r * b / kBins, hi = -r + 2 * r * (b + 1) / kBins;
      expected[std::size_t(b)] =
          kSamples *
          integrate(f, [&](double x) { return x >= lo && x < hi ? (f.eval(float(x)) < 0 ? -1.0 : 1.0) : 0.0; }) / total;
    }
    Pcg32 rng(7, 3);
    for (int i = 0; i < kSamples; ++i) {
      const float x = f.sample(rng).offset;
      ASSERT_LE(std::fabs(x), f.radius());
      count[std::size_t(std::min(kBins - 1, int((x + r) / (2 * r) * kBins)))] += 1;
    }
    double chi2 = 0, pooled_e = 0, pooled_c = 0;
    int dof = -1;
    for (int b = 0; b < kBins; ++b) {
      if (expected[std::size_t(b)] < 5) {
        pooled_e += expected[std::size_t(b)];
        pooled_c += count[std::size_t(b)];
        continue;
      }
      chi2 += std::pow(count[std::size_t(b)] - expected[std::size_t(b)], 2) / expected[std::size_t(b)];
      ++dof;
    }
    if (pooled_e >= 5) {
      chi2 += std::pow(pooled_c - pooled_e, 2) / pooled_e;
      ++dof;
    }
    EXPECT_GT(gamma_q(dof / 2.0, chi2 / 2), 1e-4) << "chi2 " << chi2 << " dof " << dof;
  }
}

// The weighted mean of g over the samples converges to ∫ f g / ∫ f, negative lobes included; filters without them
// give every sample weight 1.
TEST(PixelFilter, WeightedMeanIsTheFiltersAverage) {
  const auto g = [](double x) { return 1.0 + x + 0.7 * x * x + (x > 0.3 ? 2.0 : 0.0); };
  for (const PixelFilter& f : every_filter()) {
    SCOPED_TRACE(f.describe());
    const double want = integrate(f, g) / integrate(f, [](double) { return 1.0; });
    Pcg32 rng(11, 5);
    constexpr int kSamples = 400000;
    double sum = 0, sum2 = 0;
    bool signed_weights = false;
    for (int i = 0; i < kSamples; ++i) {
      const auto s = f.sample(rng);
      signed_weights = signed_weights || s.weight != 1.0f;
      const double v = s.weight * g(s.offset);
      sum += v;
      sum2 += v * v;
    }
    const double mean = sum / kSamples, sigma = std::sqrt((sum2 / kSamples - mean * mean) / kSamples);
    EXPECT_NEAR(mean, want, 5 * sigma + 1e-6);
    const bool has_negative_lobes =
        f.type() == Type::mitchell || f.type() == Type::catmullrom || f.type() == Type::lanczos;
    EXPECT_EQ(signed_weights, has_negative_lobes);
  }
}

// Cut by the film's edge (Mitsuba draws samples only inside the film): the offsets stay within [lo, hi] and their
// weighted mean converges to ∫ f g / ∫ f over that part of the filter, an edge pixel's value in Mitsuba's splatting.
TEST(PixelFilter, AtTheFilmsEdgeTheMeanIsOverThePartInside) {
  const auto g = [](double x) { return 1.0 + x + 0.7 * x * x + (x > 0.3 ? 2.0 : 0.0); };
  for (const PixelFilter& f : every_filter())
    for (const auto& [lo, hi] : {std::pair{-0.5f, 7.5f}, std::pair{-1.5f, 0.5f}, std::pair{-3.5f, 0.9f}}) {
      SCOPED_TRACE(f.describe() + " within [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
      const double want = integrate(f, g, lo, hi) / integrate(
                                                        f, [](double) { return 1.0; }, lo, hi);
      Pcg32 rng(13, 7);
      constexpr int kSamples = 200000;
      double sum = 0, sum2 = 0;
      bool inside = true;
      for (int i = 0; i < kSamples; ++i) {
        const auto s = f.sample(rng, lo, hi);
        inside = inside && s.offset >= lo && s.offset <= hi;
        const double v = s.weight * g(s.offset);
        sum += v;
        sum2 += v * v;
      }
      const double mean = sum / kSamples, sigma = std::sqrt((sum2 / kSamples - mean * mean) / kSamples);
      EXPECT_TRUE(inside);
      EXPECT_NEAR(mean, want, 5 * sigma + 1e-4 * std::fabs(want));
    }
}

class PixelFilterScenes : public SceneFiles {
 protected:
  // An orthographic view of [-1, 1] × [-1/4, 1/4] onto an 8 × 2 film and an emitter filling world x < 0, which is
  // the image's left half (Mitsuba's look-at frame: +x = up × forward, the image's left, is world -x here), nothing
  // else: a pixel's value is the filter's mass on the emitter's side of the edge, a pixel boundary mid-film.
  std::filesystem::path edge_scene(const std::string& rfilter) const {
    return scene(R"(
      <shape type="rectangle">
        <transform name="to_world"><scale x="5" y="5"/><translate x="-5" z="-1"/></transform>
        <emitter type="area"><rgb name="radiance" value="1"/></emitter>
      </shape>
      <sensor type="orthographic">
        <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="2"/>)" +
                 rfilter + R"(</film>
      </sensor>)");
  }
};

TEST_F(PixelFilterScenes, LoaderReadsTheRfilter) {
  EXPECT_EQ(scene::load_scene(edge_scene("")).camera.filter.type(), Type::gaussian);
  const auto tent =
      scene::load_scene(edge_scene(R"(<rfilter type="tent"><float name="radius" value="1.5"/></rfilter>)"));
  EXPECT_EQ(tent.camera.filter.type(), Type::tent);
  EXPECT_FLOAT_EQ(tent.camera.filter.radius(), 1.5f);
  const auto g =
      scene::load_scene(edge_scene(R"(<rfilter type="gaussian"><float name="stddev" value="0.25"/></rfilter>)"));
  EXPECT_FLOAT_EQ(g.camera.filter.radius(), 1.0f);
  EXPECT_EQ(scene::load_scene(edge_scene(R"(<rfilter type="lanczos"><integer name="lobes" value="2"/></rfilter>)"))
                .camera.filter.radius(),
            2.0f);
  // A resized camera keeps its film's filter.
  EXPECT_EQ(tent.camera.resized(64, 32).filter.type(), Type::tent);
  for (const char* bad :
       {R"(<rfilter type="tent"><float name="radius" value="-1"/></rfilter>)",
        R"(<rfilter type="gaussian"><float name="stddev" value="nan"/></rfilter>)",
        R"(<rfilter type="box"><float name="radius" value="1e9"/></rfilter>)",
        R"(<rfilter type="lanczos"><integer name="lobes" value="0"/></rfilter>)",
        R"(<rfilter type="tent"><float name="width" value="1"/></rfilter>)", R"(<rfilter type="sinc"/>)"}) {
    SCOPED_TRACE(bad);
    EXPECT_THROW(scene::load_scene(edge_scene(bad)), InputError);
  }
}

// Both renderers, every filter: the pixels beside the edge hold the filter's mass on the emitter's side, computed
// by quadrature; the path tracer (reference) and the model's renderer (a field of zeros: only Le) alike.
TEST_F(PixelFilterScenes, BothRenderersFilterAnEdge) {
  for (const char* rfilter : {R"(<rfilter type="box"/>)", R"(<rfilter type="tent"/>)", "",
                              R"(<rfilter type="mitchell"/>)", R"(<rfilter type="lanczos"/>)"}) {
    SCOPED_TRACE(rfilter);
    const auto s = scene::load_scene(edge_scene(rfilter));
    const PixelFilter& f = s.camera.filter;
    const geometry::Geometry geometry(s);
    // The emitter lies left of the edge (x < 4 in film pixels): pixel k's centre is k + 0.5.
    const auto expected = [&](int k) {
      const double c = k + 0.5;
      return integrate(f, [&](double x) { return c + x < 4 ? 1.0 : 0.0; }) / integrate(f, [](double) { return 1.0; });
    };
    reference::RenderOptions o;
    o.spp = 1 << 14;
    const auto pt = reference::render(geometry, o);
    radiosity::RenderSettings rs;
    rs.spp = 1 << 14;
    const auto model = radiosity::render(
        geometry, [](std::span<const float>, std::span<float> rgb) { std::fill(rgb.begin(), rgb.end(), 0.0f); }, rs);
    for (int k = 1; k < 7; ++k) {
      // Five standard deviations of the sample mean: weights of ±∫|f|/∫f on a 0/1 signal.
      const double scale = integrate(f, [&](double x) { return f.eval(float(x)) < 0 ? -1.0 : 1.0; }) /
                           integrate(f, [](double) { return 1.0; });
      const double tol = 5 * scale * 0.5 / std::sqrt(double(o.spp));
      EXPECT_NEAR(pt.pixel(k, 0)[0], expected(k), tol) << "pixel " << k;
      EXPECT_NEAR(model.pixel(k, 0)[0], expected(k), tol) << "pixel " << k;
    }
  }
}

}  // namespace
}  // namespace clr::test
