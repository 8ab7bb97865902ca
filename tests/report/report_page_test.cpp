// The report page's builder without a run or a device: the log read by column names, the HDR images carried as
// half floats, the page whole and self-contained (nothing it loads from elsewhere).
#include "report/report_page.hpp"

#include <Imath/half.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>

#include "common/error.hpp"
#include "report/half_image.hpp"
#include "report/log_table.hpp"

namespace clr::report {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("clr_report_page_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

TEST(ReportLog, ReadsColumnsByNameWhateverTheirOrderAndEmptyFields) {
  const auto p = write_file("log.csv", "seconds,step,mape\n0.5,10,\n1.5,20,0.25\n");
  const auto t = read_log_table(p);
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.values[*t.column("step")][1], 20);
  EXPECT_TRUE(std::isnan(t.values[*t.column("mape")][0]));
  EXPECT_EQ(t.values[*t.column("mape")][1], 0.25);
  EXPECT_FALSE(t.column("samples"));  // an older log lacks it: absent, not an error
  fs::remove(p);
}

TEST(ReportLog, CorruptRowsNameTheLineAndField) {
  const auto p = write_file("bad.csv", "step,seconds\n1,0.1\n2,abc\n");
  try {
    read_log_table(p);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(":3: seconds 'abc' is not a number"));
  }
  const auto q = write_file("short.csv", "step,seconds\n1\n");
  EXPECT_THROW(read_log_table(q), InputError);
  const auto r = write_file("nostep.csv", "a,b\n1,2\n");
  EXPECT_THROW(read_log_table(r), InputError);
  for (const auto& f : {p, q, r}) fs::remove(f);
}

TEST(ReportImages, Base64IsRfc4648) {
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
}

// The inverse of base64, for the test alone.
std::string unbase64(const std::string& text) {
  static const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::uint32_t bits = 0;
  int count = 0;
  for (const char c : text) {
    if (c == '=') break;
    bits = bits << 6 | std::uint32_t(alphabet.find(c));
    if ((count += 6) >= 8) out += char((bits >> (count -= 8)) & 0xff);
  }
  return out;
}

TEST(ReportImages, HalvesAreBytePlanesDeflatedAndClampedToTheirRange) {
  image::Image img(1, 1);
  img.rgb = {1.0f, 1e6f, -2.0f};
  const std::string packed = unbase64(half_base64(img));
  std::vector<Bytef> planes(6);
  uLongf size = planes.size();
  ASSERT_EQ(uncompress(planes.data(), &size, reinterpret_cast<const Bytef*>(packed.data()), uLong(packed.size())),
            Z_OK);
  // 1.0 = 0x3c00, 65504 = 0x7bff, -2 = 0xc000: the high bytes, then the low bytes.
  EXPECT_EQ(size, 6u);
  EXPECT_EQ(std::vector<Bytef>(planes.begin(), planes.begin() + 6),
            (std::vector<Bytef>{0x3c, 0x7b, 0xc0, 0x00, 0xff, 0x00}));
}

ReportData sample_data() {
  ReportData d;
  d.title = "run </script><b>x";
  image::Image a(4, 2), b(4, 2);
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    a.rgb[i] = float(i) * 0.1f;
    b.rgb[i] = float(i) * 0.11f;
  }
  d.images.push_back({"model", "model", a, {{"spp", "4"}}, image::compare(a, b)});
  d.images.push_back({"reference", "reference", b, {}, std::nullopt});
  d.log.columns = {"step", "seconds", "mape"};
  d.log.values = {{1, 2}, {0.5, 1.0}, {NAN, 0.3}};
  d.record = {{"config", {{"note", "</script><script>alert(1)</script>"}}}};
  return d;
}

TEST(ReportPage, IsOneSelfContainedPageWithTheDataInside) {
  const std::string page = report_html(sample_data());
  EXPECT_THAT(page, HasSubstr("<!DOCTYPE html>"));
  EXPECT_THAT(page, HasSubstr("</html>"));
  // Nothing is fetched: no external script, stylesheet or image.
  EXPECT_THAT(page, Not(HasSubstr("src=\"http")));
  EXPECT_THAT(page, Not(HasSubstr("href=\"http")));
  EXPECT_THAT(page, Not(HasSubstr("<link")));
  // The images travel as halves in base64, the log's empty field as null.
  EXPECT_THAT(page, HasSubstr("\"half_rgb\":\"" + half_base64(sample_data().images[0].image) + "\""));
  EXPECT_THAT(page, HasSubstr("[null,0.3]"));
  // Every mark of the template was filled.
  EXPECT_THAT(page, Not(HasSubstr("/*CLR_")));
  EXPECT_THAT(page, Not(HasSubstr("<!--CLR_")));
  // Text from the run cannot end the data's <script> or inject markup: one </script> closes each of the two.
  const std::regex close("</script>");
  EXPECT_EQ(std::distance(std::sregex_iterator(page.begin(), page.end(), close), std::sregex_iterator()), 2);
  EXPECT_THAT(page, HasSubstr("<title>run &lt;/script&gt;&lt;b&gt;x</title>"));
}

TEST(ReportPage, RefusesImagesOfDifferentSizes) {
  auto d = sample_data();
  d.images[1].image = image::Image(2, 2);
  EXPECT_THROW(report_html(d), std::invalid_argument);
}

// Issue 48's budget: a 512 × 512 run's page with its three images and 10 000 log rows stays under 20 MB and is
// assembled in well under 10 s (the browser's side, under 2 s to open, is measured by hand: docs/cli.md).
TEST(ReportPage, AFullRunsPageStaysSmallAndQuick) {
  ReportData d;
  d.title = "size";
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 4.0f);
  for (const char* key : {"model", "reference", "path_tracer"}) {
    image::Image img(512, 512);
    for (auto& v : img.rgb) v = u(rng);  // noise: the worst case for size
    d.images.push_back({key, key, std::move(img), {}, std::nullopt});
  }
  d.log.columns = {"step",       "seconds",      "loss", "lookups", "non_finite", "learning_rate", "residual_power",
                   "guide_loss", "guided_share", "mape", "mse",     "relmse",     "samples",       "mean_ratio"};
  d.log.values.assign(d.log.columns.size(), std::vector<double>(10000));
  for (auto& column : d.log.values)
    for (auto& v : column) v = double(u(rng)) / 3.0;
  const auto start = std::chrono::steady_clock::now();
  const std::string page = report_html(d);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(page.size(), 20u << 20);
  EXPECT_LT(seconds, 10.0);
  std::printf("512x512 page with 10000 log rows: %.1f MB in %.2f s\n", double(page.size()) / 1e6, seconds);
}

}  // namespace
}  // namespace clr::report
