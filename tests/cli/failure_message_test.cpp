// The runtime-failure line: out-of-memory errors name the options that size the command's buffers.
#include "cli/failure_message.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <new>

#include "cl/error.hpp"

namespace clr::test {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

cl::Error cl_error(cl_int status) {
  return cl::Error(status, "clCreateBuffer(...) failed with " + cl::status_name(status) + " at buffer.hpp:1");
}

TEST(FaultMessage, OutOfDeviceMemoryNamesTheOptionsToLower) {
  for (const cl_int status :
       {CL_OUT_OF_RESOURCES, CL_MEM_OBJECT_ALLOCATION_FAILURE, CL_INVALID_BUFFER_SIZE, CL_OUT_OF_HOST_MEMORY}) {
    const std::string train = cli::failure_message(cl_error(status), "train");
    EXPECT_THAT(train, HasSubstr(cl::status_name(status))) << "the original error stays in the line";
    EXPECT_THAT(train, HasSubstr("--batch"));
    EXPECT_THAT(train, HasSubstr("--samples"));
    EXPECT_THAT(cli::failure_message(cl_error(status), ""), HasSubstr("--batch")) << "the main job trains too";
    EXPECT_THAT(cli::failure_message(cl_error(status), "residual"), HasSubstr("--points"));
    EXPECT_THAT(cli::failure_message(cl_error(status), "render"), HasSubstr("--device"));
  }
  EXPECT_THAT(cli::failure_message(std::bad_alloc(), "train"), HasSubstr("--batch"));
}

// Host memory running out names what fills it for that command: `reference` has no model and no device.
TEST(FaultMessage, OutOfHostMemoryNamesWhatFillsIt) {
  const std::string reference = cli::failure_message(std::bad_alloc(), "reference");
  EXPECT_THAT(reference, HasSubstr("out of host memory"));
  EXPECT_THAT(reference, HasSubstr("--width"));
  EXPECT_THAT(reference, HasSubstr("meshes, textures"));
  EXPECT_THAT(reference, Not(HasSubstr("model")));
  EXPECT_THAT(reference, Not(HasSubstr("--device")));
  EXPECT_THAT(cli::failure_message(std::bad_alloc(), "compare"), HasSubstr("images"));
  EXPECT_THAT(cli::failure_message(std::bad_alloc(), "render"), Not(HasSubstr("too large for this device")));
  EXPECT_THAT(cli::failure_message(cl_error(CL_OUT_OF_RESOURCES), "render"), HasSubstr("out of device memory"));
}

TEST(FaultMessage, OtherErrorsAreLeftAsTheyAre) {
  const std::string line = cli::failure_message(cl_error(CL_INVALID_KERNEL_ARGS), "train");
  EXPECT_EQ(line, cl_error(CL_INVALID_KERNEL_ARGS).what());
  EXPECT_THAT(cli::failure_message(std::runtime_error("writing /dev/full failed"), "train"), Not(HasSubstr("--batch")));
  for (const char c : line) EXPECT_NE(c, '\n') << "one line";
}

TEST(FaultMessage, ABoundedLineKeepsShortWordsAndClipsLongOnes) {
  const std::string path = "/runs/" + std::string(300, 'a') + "/model.clr";
  const std::string line = cli::bounded_line("checkpoint " + path + " not found");
  EXPECT_THAT(line, HasSubstr("checkpoint /runs/aaa"));
  EXPECT_THAT(line, HasSubstr("…(316 bytes)…"));
  EXPECT_THAT(line, HasSubstr("/model.clr not found")) << "the end of a clipped word stays";
  EXPECT_LT(line.size(), 220u);
  const std::string plain = "--steps: 0 is not ≥ 1 (a budget of 255 characters is fine: " + std::string(250, 'b') + ")";
  EXPECT_EQ(cli::bounded_line(plain), plain);
  std::string many;
  for (int i = 0; i < 10000; ++i) many += "word ";
  EXPECT_LE(cli::bounded_line(many).size(), 4096u + 4);
}

// Whether `s` is well-formed UTF-8 holding no control character a terminal would act on.
bool terminal_safe_text(const std::string& s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 || c == 0x7f) return false;
    std::size_t n = c < 0x80 ? 1 : c >= 0xf0 ? 4 : c >= 0xe0 ? 3 : c >= 0xc2 ? 2 : 0;
    if (n == 0 || i + n > s.size()) return false;
    for (std::size_t k = 1; k < n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return false;
    if (c == 0xc2 && static_cast<unsigned char>(s[i + 1]) < 0xa0) return false;  // C1 controls
    i += n;
  }
  return true;
}

TEST(FaultMessage, ControlCharactersAreEscaped) {
  EXPECT_EQ(cli::terminal_safe("a\nb\rc\td"), "a\\nb\\rc\\td");
  EXPECT_EQ(cli::terminal_safe("\x1b[2J"), "\\x1b[2J") << "an escape sequence would clear the screen";
  EXPECT_EQ(cli::terminal_safe(std::string("nul\0!", 5)), "nul\\x00!");
  EXPECT_EQ(cli::terminal_safe("del\x7f"), "del\\x7f");
  EXPECT_EQ(cli::terminal_safe("csi \xc2\x9b"), "csi \\xc2\\x9b") << "a C1 control, the 8-bit CSI";
  EXPECT_EQ(cli::terminal_safe("bad \xff\xc3"), "bad \\xff\\xc3") << "bytes that are no UTF-8";
  EXPECT_EQ(cli::terminal_safe("overlong \xc0\xaf"), "overlong \\xc0\\xaf");
  EXPECT_EQ(cli::terminal_safe("≥ 1, Größe, 東京, 🙂"), "≥ 1, Größe, 東京, 🙂")
      << "well-formed UTF-8 stays";
  const std::string line = cli::bounded_line("scene 'x\ny': not found");
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_EQ(line, "scene 'x\\ny': not found");
}

TEST(FaultMessage, ClippingNeverCutsACharacter) {
  // Long words of 2-, 3- and 4-byte characters, at every offset against the clipping points.
  for (const std::string ch : {"é", "東", "🙂"})
    for (int pad = 0; pad < 4; ++pad) {
      std::string word(std::size_t(pad), 'x');
      while (word.size() < 400) word += ch;
      const std::string line = cli::bounded_line("value " + word + " refused");
      EXPECT_TRUE(terminal_safe_text(line)) << "pad " << pad << ": " << line;
      EXPECT_THAT(line, HasSubstr("bytes)…"));
    }
  std::string many;
  for (int i = 0; i < 3000; ++i) many += "東京 ";
  EXPECT_TRUE(terminal_safe_text(cli::bounded_line(many))) << "the line's own limit";
}

}  // namespace
}  // namespace clr::test
