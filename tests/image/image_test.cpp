// Image files, downsampling and the metrics of docs/design.md §4, against hand-computed values.
#include "image/image.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "common/error.hpp"
#include "image/srgb.hpp"
#include "support/run_cli.hpp"
#include "support/shared_scenes.hpp"

namespace clr::image {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class TempDir {
 public:
  TempDir() : path(fs::temp_directory_path() / ("clr_image_" + std::to_string(::getpid()))) {
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  fs::path path;
};

Image ramp(int w, int h) {
  Image img(w, h);
  for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = 0.01f * float(i) - 0.3f;
  return img;
}

TEST(ImageIo, ExrRoundTripIsExactAndLeavesNoTempFile) {
  TempDir dir;
  const Image img = ramp(7, 5);
  write_exr(dir.path / "a.exr", img);
  const Image back = read_exr(dir.path / "a.exr");
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(back.rgb, img.rgb);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()), 1);
}

TEST(ImageIo, PngIsSrgbEncodedAndReadsBack) {
  TempDir dir;
  Image img(3, 1);
  const float values[3] = {0.0f, 0.2158605f /* sRGB 128/255 */, 4.0f /* clamps */};
  for (int x = 0; x < 3; ++x)
    for (int c = 0; c < 3; ++c) img.pixel(x, 0)[c] = values[x];
  write_png(dir.path / "a.png", img);
  const Image raw = read_ldr(dir.path / "a.png", false);
  EXPECT_NEAR(raw.pixel(0, 0)[0], 0.0f, 1e-6);
  EXPECT_NEAR(raw.pixel(1, 0)[0], 128.0f / 255.0f, 1e-6);
  EXPECT_NEAR(raw.pixel(2, 0)[0], 1.0f, 1e-6);
  const Image lin = read_ldr(dir.path / "a.png", true);
  EXPECT_NEAR(lin.pixel(1, 0)[1], 0.2158605f, 1e-5);  // sRGB 128/255 decoded
}

// Every byte value, decoded through the loader's table, against the sRGB curve in double precision.
TEST(ImageIo, EveryEightBitValueDecodesByTheSrgbCurve) {
  TempDir dir;
  Image img(256, 1);
  for (int b = 0; b < 256; ++b)
    for (int c = 0; c < 3; ++c) img.pixel(b, 0)[c] = srgb_to_linear(float(b) / 255.0f);
  write_png(dir.path / "ramp.png", img);
  const Image raw = read_ldr(dir.path / "ramp.png", false);
  const Image lin = read_ldr(dir.path / "ramp.png", true);
  for (int b = 0; b < 256; ++b) {
    ASSERT_EQ(raw.pixel(b, 0)[2], float(b) / 255.0f) << "byte " << b << " did not survive the PNG";
    const double v = b / 255.0, want = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(lin.pixel(b, 0)[c], want, 1e-6 * want + 1e-9) << "byte " << b;
  }
}

TEST(ImageIo, MissingAndCorruptFilesAreInputErrors) {
  TempDir dir;
  EXPECT_THROW(read_exr(dir.path / "missing.exr"), InputError);
  std::ofstream(dir.path / "bad.exr") << "not an exr";
  try {
    read_exr(dir.path / "bad.exr");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("bad.exr"));
  }
  std::ofstream(dir.path / "bad.png") << "not a png";
  EXPECT_THROW(read_ldr(dir.path / "bad.png", true), InputError);
}

TEST(Metrics, MatchHandComputedValues) {
  Image a(1, 1), b(1, 1);
  a.rgb = {1.0f, 0.5f, 0.0f};
  b.rgb = {0.5f, 0.5f, 0.1f};
  const Metrics m = compare(a, b);
  EXPECT_NEAR(m.mape, (0.5 / 0.51 + 0.0 + 0.1 / 0.11) / 3, 1e-6);
  EXPECT_NEAR(m.mse, (0.25 + 0.0 + 0.01) / 3, 1e-6);
  EXPECT_NEAR(m.relmse, (0.25 / 0.26 + 0.0 + 0.01 / 0.02) / 3, 1e-6);
  EXPECT_NEAR(m.mean_ratio, 1.5 / 1.1, 1e-6);
  EXPECT_EQ(compare(b, b).mape, 0.0);
  EXPECT_EQ(compare(b, b).mean_ratio, 1.0);
  Image black(1, 1);
  EXPECT_TRUE(std::isnan(compare(a, black).mean_ratio)) << "no brightness to compare with";
}

TEST(Metrics, NonFiniteValuesInTheImageMakeEveryMetricNonFinite) {
  Image a(2, 1), b(2, 1);
  b.rgb = {1, 1, 1, 1, 1, 1};
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    a.rgb = {1, 1, 1, bad, 1, 1};
    const Metrics m = compare(a, b);
    EXPECT_EQ(m.non_finite, 1u);
    EXPECT_TRUE(std::isnan(m.mape) && std::isnan(m.mse) && std::isnan(m.relmse) && std::isnan(m.mean_ratio))
        << "a mean over the rest hid it";
    EXPECT_THAT(describe(m), HasSubstr("1 non-finite values in the image"));
  }
  a.rgb.assign(6, std::numeric_limits<float>::quiet_NaN());
  EXPECT_TRUE(std::isnan(compare(a, b).mape)) << "an all-NaN image scored as perfect";
}

TEST(Metrics, NonFiniteReferenceValuesAreLeftOutAndCounted) {
  Image a(2, 1), b(2, 1);
  a.rgb = {1, 1, 1, 2, 2, 2};
  b.rgb = {1, 1, 1, std::numeric_limits<float>::quiet_NaN(), 2, 2};
  const Metrics m = compare(a, b);
  EXPECT_EQ(m.non_finite, 0u);
  EXPECT_EQ(m.reference_non_finite, 1u);
  EXPECT_EQ(m.mse, 0.0);
  EXPECT_EQ(m.mean_ratio, 1.0) << "the left-out value counts on neither side";
  EXPECT_THAT(describe(m), HasSubstr("1 non-finite values in the reference"));
}

TEST(Metrics, ReferenceIsDownsampledOnlyByAnIntegerFactor) {
  const Image ref = ramp(8, 4);
  const Image down = match_size(ref, Image(4, 2));
  ASSERT_EQ(down.width, 4);
  // Pixel (0,0) averages (0,0),(1,0),(0,1),(1,1) of the ramp.
  const auto v = [&](int x, int y) { return ref.pixel(x, y)[0]; };
  EXPECT_NEAR(down.pixel(0, 0)[0], (v(0, 0) + v(1, 0) + v(0, 1) + v(1, 1)) / 4, 1e-6);
  EXPECT_THROW(match_size(ref, Image(3, 2)), InputError);
  EXPECT_THROW(match_size(ref, Image(4, 4)), InputError);  // unequal factors would distort
  EXPECT_THROW(compare(ref, Image(4, 2)), InputError);
}

TEST(CompareCommand, PrintsMetricsAndRejectsBadInput) {
  TempDir dir;
  Image a(2, 2), ref(4, 4);
  std::fill(a.rgb.begin(), a.rgb.end(), 1.0f);
  std::fill(ref.rgb.begin(), ref.rgb.end(), 0.5f);
  write_exr(dir.path / "a.exr", a);
  write_exr(dir.path / "ref.exr", ref);
  auto r = clr::test::run_cli("compare " + (dir.path / "a.exr").string() + " " + (dir.path / "ref.exr").string() +
                              " --json --error-map " + (dir.path / "err.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("\"mape\":0.98039"));  // 0.5 / 0.51
  EXPECT_THAT(r.out, HasSubstr("\"mean_ratio\":2.0"));
  EXPECT_TRUE(fs::exists(dir.path / "err.png"));

  r = clr::test::run_cli("compare " + (dir.path / "ref.exr").string() + " " + (dir.path / "a.exr").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("integer multiple"));
  r = clr::test::run_cli("compare " + (dir.path / "nope.exr").string() + " " + (dir.path / "a.exr").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("nope.exr"));
}

TEST(CompareCommand, TungstenReferenceLoads) {
  const fs::path ref = clr::test::shared_scenes() / "cornell-box" / "TungstenRender.exr";
  CLR_REQUIRE_SHARED(ref);
  const Image img = read_exr(ref);
  EXPECT_EQ(img.width, 1024);
  EXPECT_EQ(img.height, 1024);
  double mean = 0;
  for (float v : img.rgb) {
    ASSERT_TRUE(std::isfinite(v));
    mean += v;
  }
  EXPECT_GT(mean / double(img.rgb.size()), 0.01);
}

}  // namespace
}  // namespace clr::image
