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

}  // namespace
}  // namespace clr::test
