// Every BSDF's sample() against its pdf() (χ²), its weights against eval()/pdf(), and its eval() against the
// integral of f·cos over the sphere; delta lobes against the laws they implement.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "scene/bsdfs.hpp"
#include "scene/chi2.hpp"
#include "scene/fresnel.hpp"
#include "scene/named_ior.hpp"

namespace clr::test {
namespace {

using scene::Microfacet;
using scene::Rgb;
using scene::Vec2;
using scene::Vec3;

Vec3 direction(float theta_degrees, float phi_degrees = 20.0f) {
  const float t = theta_degrees * scene::kPi / 180.0f, p = phi_degrees * scene::kPi / 180.0f;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

struct Case {
  std::string name;
  std::function<std::shared_ptr<const scene::Bsdf>()> make;
  float theta_o;  // degrees; above 90: wo below the surface
  // Upper bound of ∫ f·cos dω: 1 for a passive surface, except that radiance leaving a dense medium is scaled up
  // by η² (the same light spreads over a smaller solid angle outside), so transmission from inside reaches η².
  float max_albedo = 1.0f;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

Microfacet mf(Microfacet::Type t, float alpha) { return {t, alpha}; }
Microfacet mf(Microfacet::Type t, float alpha_u, float alpha_v) { return {t, alpha_u, alpha_v}; }
constexpr auto kBeckmann = Microfacet::Type::beckmann;
constexpr auto kGgx = Microfacet::Type::ggx;
const scene::ComplexIor kGold = *scene::conductor_ior("Au");

std::vector<Case> cases() {
  auto diffuse = [] { return std::make_shared<scene::Diffuse>(Rgb(0.7f, 0.5f, 0.3f)); };
  auto conductor = [](Microfacet m) {
    return [m] { return std::make_shared<scene::Conductor>(kGold.eta, kGold.k, Rgb(1.0f), m); };
  };
  auto plastic = [](std::optional<Microfacet> m, bool nonlinear) {
    return [m, nonlinear] {
      return std::make_shared<scene::Plastic>(1.5f, Rgb(0.6f, 0.3f, 0.2f), Rgb(1.0f), nonlinear, m);
    };
  };
  auto pplastic = [](Microfacet m) {
    return [m] { return std::make_shared<scene::PolarizedPlastic>(1.49f, Rgb(0.05f, 0.3f, 0.6f), std::nullopt, m); };
  };
  auto rough_glass = [](Microfacet m) {
    return [m] {
      return std::make_shared<scene::Dielectric>(scene::Dielectric::Kind::rough, 1.5f, Rgb(1.0f), Rgb(1.0f), m);
    };
  };
  // Textured roughness whose texels (0.35, 0.15) differ from the lobe's stand-in alphas (0.1): eval, pdf and sample
  // must all read the texels.
  const scene::RoughnessTextures texels{scene::Texture(Rgb(0.35f)), scene::Texture(Rgb(0.15f))};
  auto textured_glass = [texels](Microfacet m) {
    return [m, texels] {
      return std::make_shared<scene::Dielectric>(scene::Dielectric::Kind::rough, 1.5f, Rgb(1.0f), Rgb(1.0f), m, texels);
    };
  };
  auto textured_conductor = [texels](Microfacet m) {
    return [m, texels] { return std::make_shared<scene::Conductor>(kGold.eta, kGold.k, Rgb(1.0f), m, texels); };
  };
  auto principled = [](scene::Principled::Params q) { return [q] { return std::make_shared<scene::Principled>(q); }; };
  return {
      {"diffuse", diffuse, 30},
      {"roughdiffuse_full",
       [] { return std::make_shared<scene::RoughDiffuse>(Rgb(0.8f, 0.5f, 0.2f), Rgb(0.5f), false); }, 50},
      {"roughdiffuse_fast", [] { return std::make_shared<scene::RoughDiffuse>(Rgb(0.8f), Rgb(0.3f), true); }, 20},
      {"phong_30", [] { return std::make_shared<scene::Phong>(Rgb(0.5f), Rgb(0.2f), 30.0f); }, 35},
      {"phong_5_grazing", [] { return std::make_shared<scene::Phong>(Rgb(0.3f, 0.2f, 0.1f), Rgb(0.6f), 5.0f); }, 70},
      {"ward_balanced_anisotropic",
       [] { return std::make_shared<scene::Ward>(scene::Ward::Variant::balanced, Rgb(0.4f), Rgb(0.3f), 0.1f, 0.3f); },
       40},
      {"ward_duer",
       [] { return std::make_shared<scene::Ward>(scene::Ward::Variant::ward_duer, Rgb(0.3f), Rgb(0.2f), 0.2f, 0.2f); },
       30},
      {"twosided_diffuse_back", [=] { return std::make_shared<scene::TwoSided>(diffuse(), diffuse()); }, 130},
      {"roughconductor_beckmann_0_2", conductor(mf(kBeckmann, 0.2f)), 30},
      {"roughconductor_beckmann_0_5_grazing", conductor(mf(kBeckmann, 0.5f)), 75},
      {"roughconductor_ggx_0_2", conductor(mf(kGgx, 0.2f)), 30},
      {"roughconductor_ggx_0_5_grazing", conductor(mf(kGgx, 0.5f)), 75},
      {"roughconductor_beckmann_anisotropic", conductor(mf(kBeckmann, 0.1f, 0.4f)), 40},
      {"roughconductor_ggx_anisotropic_grazing", conductor(mf(kGgx, 0.5f, 0.15f)), 70},
      {"plastic", plastic(std::nullopt, false), 40},
      {"plastic_nonlinear", plastic(std::nullopt, true), 70},
      {"roughplastic_ggx_0_3", plastic(mf(kGgx, 0.3f), false), 40},
      {"roughplastic_beckmann_0_2", plastic(mf(kBeckmann, 0.2f), true), 60},
      {"pplastic_beckmann_0_1", pplastic(mf(kBeckmann, 0.1f)), 40},
      {"pplastic_ggx_0_4_grazing", pplastic(mf(kGgx, 0.4f)), 75},
      {"blend_diffuse_roughconductor",
       [=] { return std::make_shared<scene::BlendBsdf>(Rgb(0.3f), diffuse(), conductor(mf(kGgx, 0.15f))()); }, 45},
      {"roughdielectric_ggx_outside", rough_glass(mf(kGgx, 0.3f)), 35},
      {"roughdielectric_ggx_inside", rough_glass(mf(kGgx, 0.3f)), 160, 1.5f * 1.5f},
      {"roughdielectric_beckmann_outside", rough_glass(mf(kBeckmann, 0.4f)), 60},
      {"roughdielectric_textured_outside", textured_glass(mf(kGgx, 0.1f)), 40},
      {"roughdielectric_textured_inside", textured_glass(mf(kBeckmann, 0.1f)), 155, 1.5f * 1.5f},
      {"roughconductor_textured", textured_conductor(mf(kGgx, 0.1f)), 50},
      {"roughdielectric_ggx_anisotropic_inside", rough_glass(mf(kGgx, 0.1f, 0.35f)), 150, 1.5f * 1.5f},
      {"pplastic_ggx_anisotropic", pplastic(mf(kGgx, 0.3f, 0.08f)), 50},
      {"roughdielectric_beckmann_inside", rough_glass(mf(kBeckmann, 0.2f)), 170, 1.5f * 1.5f},
      {"principled_default", principled({}), 30},
      {"principled_metallic_anisotropic_grazing",
       principled({.base_color = Rgb(0.9f, 0.6f, 0.2f),
                   .values = {.roughness = 0.3f, .anisotropic = 0.6f, .metallic = 0.7f, .spec_tint = 0.4f}}),
       70},
      {"principled_clearcoat_sheen_flatness",
       principled({.base_color = Rgb(0.2f, 0.5f, 0.8f),
                   .values = {.roughness = 0.6f,
                              .sheen = 0.6f,
                              .sheen_tint = 0.5f,
                              .flatness = 0.4f,
                              .clearcoat = 0.8f,
                              .clearcoat_gloss = 0.5f}}),
       45},
      {"principled_glossy_clearcoat_rates",
       principled({.base_color = Rgb(0.3f),
                   .values = {.roughness = 0.15f, .clearcoat = 1.0f, .clearcoat_gloss = 0.2f},
                   .eta = 1.8f,
                   .clearcoat_rate = 3.0f,
                   .diffuse_rate = 0.5f}),
       20},
      {"principled_spec_trans_outside",
       principled(
           {.base_color = Rgb(0.8f, 0.9f, 0.6f),
            .values = {.roughness = 0.3f, .metallic = 0.1f, .sheen = 0.2f, .clearcoat = 0.3f, .spec_trans = 0.7f}}),
       40},
      {"principled_spec_trans_inside", principled({.values = {.roughness = 0.4f, .spec_trans = 0.8f}}), 150,
       1.5f * 1.5f},
      {"principledthin_default",
       [] { return std::make_shared<scene::PrincipledThin>(scene::PrincipledThin::Params{}); }, 35},
      {"principledthin_all_lobes_from_below",
       [] {
         return std::make_shared<scene::PrincipledThin>(
             scene::PrincipledThin::Params{.base_color = Rgb(0.7f, 0.4f, 0.2f),
                                           .values = {.roughness = 0.4f,
                                                      .anisotropic = 0.4f,
                                                      .spec_trans = 0.6f,
                                                      .diff_trans = 0.8f,
                                                      .spec_tint = 0.5f,
                                                      .sheen = 0.5f,
                                                      .sheen_tint = 0.3f,
                                                      .flatness = 0.3f,
                                                      .eta = 1.4f}});
       },
       130},
      {"principled_spec_trans_full_grazing",
       principled({.values = {.roughness = 0.25f, .spec_trans = 1.0f}, .eta = 1.33f}), 75},
  };
}

class BsdfSampling : public ::testing::TestWithParam<Case> {};

TEST_P(BsdfSampling, Chi2MatchesPdf) {
  const auto bsdf = GetParam().make();
  const auto r = chi2_test(*bsdf, direction(GetParam().theta_o), 1'000'000, 7);
  ASSERT_TRUE(r.problem.empty()) << r.problem;
  // α = 0.01 over the whole suite, Šidák-corrected for the number of BSDFs tested.
  const double alpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / double(cases().size()));
  EXPECT_GT(r.p_value, alpha) << "χ² rejects sample() against pdf(): p = " << r.p_value << ", dof " << r.dof;
}

TEST_P(BsdfSampling, WeightsMatchEvalOverPdfAndIntegrateFCos) {
  const auto bsdf = GetParam().make();
  const Vec3 wo = direction(GetParam().theta_o);
  const Vec2 uv(0.5f);
  // E[weight] over the non-delta samples must equal ∫ f·cos dω (f·cos from eval, integrated by quadrature).
  constexpr int kN = 400'000;
  Pcg32 rng(1, 99);
  glm::dvec3 sum(0.0), sum2(0.0);
  for (int i = 0; i < kN; ++i) {
    const auto bs = bsdf->sample(uv, wo, rng.next_float(), {rng.next_float(), rng.next_float()});
    if (!bs || bs->delta) continue;
    const Rgb f = bsdf->eval(uv, wo, bs->wi);
    const float p = bsdf->pdf(uv, wo, bs->wi);
    ASSERT_GT(p, 0.0f);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(bs->weight[c], f[c] / p, 1e-3f * (1.0f + f[c] / p)) << "sample " << i;
    ASSERT_NEAR(bs->pdf, p, 1e-3f * p);
    sum += glm::dvec3(bs->weight);
    sum2 += glm::dvec3(bs->weight) * glm::dvec3(bs->weight);
  }
  const auto cells = SphereGrid::integrate([&](const Vec3& w) { return double(bsdf->eval(uv, wo, w).x); });
  double integral = 0;
  for (double c : cells) integral += c;
  const double mean = sum.x / kN, se = std::sqrt(std::max(0.0, sum2.x / kN - mean * mean) / kN);
  // 5 standard errors of the estimate plus 0.5 % for the quadrature of peaked lobes.
  EXPECT_NEAR(mean, integral, 5 * se + 0.005 * integral);
  EXPECT_LE(integral, GetParam().max_albedo + 1e-3) << "a passive surface scatters at most what arrives";
}

INSTANTIATE_TEST_SUITE_P(All, BsdfSampling, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& param_info) { return param_info.param.name; });

// The χ² test must be able to fail: cosine-weighted samples claimed to be uniform over the hemisphere.
class MislabelledDiffuse final : public scene::Bsdf {
 public:
  Rgb eval(const scene::TexturePoint&, const Vec3&, const Vec3& wi) const override {
    return Rgb(wi.z > 0 ? wi.z / scene::kPi : 0);
  }
  float pdf(const scene::TexturePoint&, const Vec3&, const Vec3& wi) const override {
    return wi.z > 0 ? 0.5f / scene::kPi : 0;
  }
  std::optional<scene::BsdfSample> sample(const scene::TexturePoint&, const Vec3&, float,
                                          const Vec2& u) const override {
    const Vec3 wi = scene::sample_cosine_hemisphere(u);
    return scene::BsdfSample{wi, Rgb(1.0f), 0.5f / scene::kPi, false};
  }
  Rgb albedo(const scene::TexturePoint&) const override { return Rgb(1.0f); }
  float roughness() const override { return 1.0f; }
  bool has_non_delta() const override { return true; }
};

TEST(Chi2, RejectsAPdfThatDoesNotDescribeTheSampler) {
  const auto r = chi2_test(MislabelledDiffuse(), direction(30), 100'000, 3);
  EXPECT_LT(r.p_value, 1e-9);
}

TEST(Fresnel, ConductorWithoutAbsorptionIsDielectric) {
  for (float eta : {1.2f, 1.5f, 2.4f})
    for (float c : {0.05f, 0.3f, 0.7f, 1.0f})
      EXPECT_NEAR(scene::fresnel_conductor(c, Rgb(eta), Rgb(0.0f)).x, scene::fresnel_dielectric(c, eta).reflectance,
                  1e-5f);
}

TEST(Fresnel, NormalIncidenceAndTotalInternalReflection) {
  EXPECT_NEAR(scene::fresnel_dielectric(1.0f, 1.5f).reflectance, 0.04f, 1e-6f);  // ((η−1)/(η+1))²
  const float critical = std::sqrt(1.0f - 1.0f / (1.5f * 1.5f));                 // cos of the critical angle
  EXPECT_EQ(scene::fresnel_dielectric(-(critical - 1e-3f), 1.5f).reflectance, 1.0f);
  EXPECT_LT(scene::fresnel_dielectric(-(critical + 1e-3f), 1.5f).reflectance, 1.0f);
  const Rgb f0 = scene::fresnel_conductor(1.0f, kGold.eta, kGold.k);
  for (int c = 0; c < 3; ++c) {
    const float n = kGold.eta[c], k = kGold.k[c];
    EXPECT_NEAR(f0[c], ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k), 1e-5f);
  }
}

TEST(Fresnel, DiffuseReflectanceConservesEnergyAcrossTheInterface) {
  // Light leaving a slab diffusely: 1 − F_int = (1 − F_ext)/η² (a consequence of reciprocity and étendue).
  for (float eta : {1.33f, 1.5f, 2.0f})
    EXPECT_NEAR(1.0f - scene::diffuse_fresnel_reflectance(1.0f / eta),
                (1.0f - scene::diffuse_fresnel_reflectance(eta)) / (eta * eta), 1e-4f);
  EXPECT_NEAR(scene::diffuse_fresnel_reflectance(1.0f), 0.0f, 1e-6f);
}

TEST(DeltaBsdfs, MirrorReflectsWithConductorFresnel) {
  const scene::Conductor mirror(kGold.eta, kGold.k, Rgb(0.5f), std::nullopt);
  const Vec3 wo = direction(50);
  const auto s = mirror.sample(Vec2(0), wo, 0.3f, Vec2(0.1f, 0.2f));
  ASSERT_TRUE(s && s->delta);
  EXPECT_NEAR(glm::length(s->wi - Vec3(-wo.x, -wo.y, wo.z)), 0.0f, 1e-6f);
  const Rgb f = scene::fresnel_conductor(wo.z, kGold.eta, kGold.k) * 0.5f;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(s->weight[c], f[c], 1e-6f);
  EXPECT_EQ(mirror.pdf(Vec2(0), wo, s->wi), 0.0f);
  EXPECT_FALSE(mirror.has_non_delta());
}

TEST(DeltaBsdfs, GlassRefractsBySnellAndScalesRadiance) {
  const scene::Dielectric glass(scene::Dielectric::Kind::smooth, 1.5f, Rgb(1.0f), Rgb(1.0f), std::nullopt);
  const Vec3 wo = direction(40);
  const float fresnel = scene::fresnel_dielectric(wo.z, 1.5f).reflectance;
  const auto r = glass.sample(Vec2(0), wo, 0.5f * fresnel, Vec2(0.5f));
  ASSERT_TRUE(r && r->delta);
  EXPECT_GT(r->wi.z, 0.0f);
  EXPECT_NEAR(r->pdf, fresnel, 1e-6f);
  const auto t = glass.sample(Vec2(0), wo, 0.99f, Vec2(0.5f));
  ASSERT_TRUE(t && t->delta);
  const float sin_o = std::sqrt(1 - wo.z * wo.z), sin_i = std::sqrt(1 - t->wi.z * t->wi.z);
  EXPECT_LT(t->wi.z, 0.0f);
  EXPECT_NEAR(sin_o, 1.5f * sin_i, 1e-5f);                              // Snell
  EXPECT_NEAR(glm::dot(Vec2(wo), Vec2(t->wi)), -sin_o * sin_i, 1e-5f);  // in the plane of incidence, opposite side
  EXPECT_NEAR(t->weight.x, 1.0f / (1.5f * 1.5f), 1e-5f);                // entering: radiance compressed by 1/η²
  // From inside, beyond the critical angle, everything reflects.
  const auto tir = glass.sample(Vec2(0), -direction(60), 0.999f, Vec2(0.5f));
  ASSERT_TRUE(tir);
  EXPECT_LT(tir->wi.z, 0.0f);
  EXPECT_NEAR(tir->pdf, 1.0f, 1e-6f);
}

TEST(DeltaBsdfs, ThinGlassPassesStraightThroughAndSumsInternalReflections) {
  const scene::Dielectric thin(scene::Dielectric::Kind::thin, 1.5f, Rgb(1.0f), Rgb(1.0f), std::nullopt);
  const Vec3 wo = direction(30);
  const float r = scene::fresnel_dielectric(wo.z, 1.5f).reflectance, t = 1 - r;
  const float slab = r + t * t * r / (1 - r * r);
  const auto refl = thin.sample(Vec2(0), wo, 0.0f, Vec2(0.5f));
  ASSERT_TRUE(refl);
  EXPECT_NEAR(refl->pdf, slab, 1e-6f);
  const auto trans = thin.sample(Vec2(0), wo, 0.999f, Vec2(0.5f));
  ASSERT_TRUE(trans);
  EXPECT_NEAR(glm::length(trans->wi + wo), 0.0f, 1e-6f);
  EXPECT_NEAR(trans->pdf, 1 - slab, 1e-6f);
}

TEST(TwoSided, BackSideMirrorsFront) {
  const auto front = std::make_shared<scene::Diffuse>(Rgb(0.5f));
  const auto back = std::make_shared<scene::Diffuse>(Rgb(0.25f));
  const scene::TwoSided two(front, back);
  const Vec3 wo = direction(30), wi = direction(60, 200);
  EXPECT_NEAR(two.eval(Vec2(0), wo, wi).x, 0.5f / scene::kPi * wi.z, 1e-6f);
  const Vec3 wo_b(wo.x, wo.y, -wo.z), wi_b(wi.x, wi.y, -wi.z);
  EXPECT_NEAR(two.eval(Vec2(0), wo_b, wi_b).x, 0.25f / scene::kPi * wi.z, 1e-6f);
  EXPECT_EQ(two.eval(Vec2(0), wo_b, wi).x, 0.0f);                          // no transmission
  EXPECT_EQ(scene::Diffuse(Rgb(0.5f)).eval(Vec2(0), wo_b, wi_b).x, 0.0f);  // one-sided without the wrapper
}

TEST(RoughDiffuse, LambertianWhenSmoothAndReciprocal) {
  const scene::RoughDiffuse smooth(Rgb(0.6f), Rgb(0.0f), false), rough(Rgb(0.6f), Rgb(0.7f), false),
      fast(Rgb(0.6f), Rgb(0.7f), true);
  for (const float to : {10.0f, 50.0f, 80.0f})
    for (const float ti : {5.0f, 40.0f, 85.0f}) {
      const Vec3 wo = direction(to, 20.0f), wi = direction(ti, 140.0f);
      EXPECT_NEAR(smooth.eval(Vec2(0), wo, wi).x, 0.6f * scene::kInvPi * wi.z, 1e-6f);  // σ = 0: Lambert
      for (const scene::RoughDiffuse* b : {&rough, &fast})
        EXPECT_NEAR(b->eval(Vec2(0), wo, wi).x / wi.z, b->eval(Vec2(0), wi, wo).x / wo.z,
                    1e-5f);  // f(wo, wi) = f(wi, wo)
    }
}

// Mitsuba 3.9's bumpmap and normalmap around the nested BSDF (scene::BsdfPoint), against a double-precision twin:
// Estevez et al.'s shadowing term 2 / (1 + √(1 + α²·tan²θi)), α² = min(tan²θn / 8, 1), on f and on the sample
// weight, and a tilt the viewer sees from the wrong side mirrored about the untilted normal. Without the two, a
// bump-mapped principled glass rendered 1.2 % brighter than in Mitsuba (docs/scenes.md).
double shadowing_twin(const glm::dvec3& tilted, const glm::dvec3& untilted, const glm::dvec3& wi) {
  const double cn = glm::dot(tilted, untilted), ci = glm::dot(wi, untilted);
  const double alpha2 = std::min(0.125 * (1 - cn * cn) / (cn * cn), 1.0);
  return 2.0 / (1.0 + std::sqrt(1.0 + alpha2 * (1 - ci * ci) / (ci * ci)));
}

TEST(BumpedFrames, ShadowTheBsdfAndMirrorATiltSeenFromBelow) {
  const scene::Diffuse diffuse(Rgb(0.6f));
  const Vec3 up(0, 0, 1), tilted = glm::normalize(Vec3(-1, 0, 2));  // tan θn = 1/2: α² = 1/32
  const scene::BsdfPoint p{&diffuse, scene::Frame(tilted), {}, up};
  const glm::dvec3 up_d(0, 0, 1);
  // wi 60° from the untilted normal: tan²θi = 3, a fixed value as well as the twin's.
  const Vec3 wi = glm::normalize(Vec3(0, std::sqrt(3.0f), 1));
  EXPECT_NEAR(p.shadowing(p.frame, wi), 2.0 / (1.0 + std::sqrt(1.0 + 3.0 / 32)), 1e-6);

  const auto lambert = [&](const glm::dvec3& n, const Vec3& w, const Vec3& to) {
    return 0.6 / scene::kPi * std::max(0.0, glm::dot(n, glm::dvec3(to))) *
           shadowing_twin(n, up_d, glm::dvec3(glm::normalize(glm::dvec3(w))));
  };
  // A viewer above both normals: the tilted frame as it is, f·cos times the shadowing.
  const Vec3 wo = glm::normalize(Vec3(-1, 0, 3));
  for (const Vec3& w : {wi, glm::normalize(Vec3(0.3f, -0.2f, 1)), glm::normalize(Vec3(-0.8f, 0.1f, 0.3f))})
    EXPECT_NEAR(p.eval(wo, w).x, lambert(glm::dvec3(tilted), w, w), 1e-6) << w.x << " " << w.y << " " << w.z;

  // A viewer above the untilted normal and below the tilted one: the frame is the tilt mirrored, n' ∝ (1, 0, 2).
  // Without the mirror the diffuse lobe, seen from below, was black there.
  const Vec3 grazing = glm::normalize(Vec3(1, 0, 0.2f));
  ASSERT_LT(glm::dot(grazing, tilted), 0.0f);
  const glm::dvec3 mirrored = glm::normalize(glm::dvec3(1, 0, 2));
  EXPECT_NEAR(glm::length(glm::dvec3(p.frame_seen_from(grazing).n) - mirrored), 0.0, 1e-6);
  EXPECT_NEAR(p.eval(grazing, wi).x, lambert(mirrored, wi, wi), 1e-6);
  EXPECT_GT(p.eval(grazing, wi).x, 0.0f);
  // Below the mirrored normal but above the untilted one: no light across it.
  EXPECT_EQ(p.eval(grazing, glm::normalize(Vec3(-1, 0, 0.2f))).x, 0.0f);
  // Training and the model's renders take the side a viewer scatters from as eval does: above the untilted normal.
  EXPECT_TRUE(p.seen_from_scattering_side(grazing)) << "lit, though below the tilted normal";
  EXPECT_FALSE(p.seen_from_scattering_side(glm::normalize(Vec3(-1, 0, -0.2f)))) << "below the untilted normal";
  EXPECT_EQ(p.eval(glm::normalize(Vec3(-1, 0, -0.2f)), wi).x, 0.0f);
  const scene::BsdfPoint flat{&diffuse, scene::Frame(up), {}, Vec3(0.0f)};
  EXPECT_FALSE(flat.seen_from_scattering_side(grazing * Vec3(1, 1, -1))) << "no tilt: the shading normal's side";
  EXPECT_TRUE(flat.seen_from_scattering_side(grazing));

  // Samples carry the shadowing in their weight (the density is the nested BSDF's): weight = eval / pdf.
  Pcg32 rng(5, 7);
  for (const Vec3& from : {wo, grazing})
    for (int i = 0; i < 200; ++i) {
      const auto s = p.sample(from, rng.next_float(), {rng.next_float(), rng.next_float()});
      if (!s) continue;
      EXPECT_NEAR(s->weight.x, p.eval(from, s->wi).x / p.pdf(from, s->wi), 1e-4f);
      EXPECT_LT(s->weight.x, 0.6f + 1e-6f);  // the diffuse albedo, less what the shadowing takes
    }

  // A smooth glass seen from the wrong side of the tilt is entered from outside, at the mirrored normal: its
  // reflection is the mirror image about n', its weight Fresnel's share (chosen with that probability) shadowed.
  const scene::Dielectric glass(scene::Dielectric::Kind::smooth, 1.5f, Rgb(1.0f), Rgb(1.0f), std::nullopt);
  const scene::BsdfPoint g{&glass, scene::Frame(tilted), {}, up};
  const auto r = g.sample(grazing, 0.0f, {0.5f, 0.5f});  // u_lobe 0: the reflection
  ASSERT_TRUE(r.has_value());
  const glm::dvec3 want = 2.0 * glm::dot(glm::dvec3(grazing), mirrored) * mirrored - glm::dvec3(grazing);
  EXPECT_NEAR(glm::length(glm::dvec3(r->wi) - want), 0.0, 1e-5);
  EXPECT_NEAR(r->weight.x, shadowing_twin(mirrored, up_d, want), 1e-5);
}

}  // namespace
}  // namespace clr::test
