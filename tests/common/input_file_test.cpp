// JSON inputs: the nesting limit is found in one linear pass, brackets inside strings are not nesting, and a
// large document parses in time proportional to its size.
#include "common/input_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>

#include "common/error.hpp"

namespace clr::test {
namespace {

using ::testing::HasSubstr;

std::string nested(int depth) { return std::string(std::size_t(depth), '[') + std::string(std::size_t(depth), ']'); }

TEST(InputFile, JsonNestingUpToTheLimitIsRead) {
  EXPECT_NO_THROW(parse_json(nested(kMaxJsonDepth), "test"));
  try {
    parse_json(nested(kMaxJsonDepth + 1), "test");
    FAIL() << "nesting beyond the limit was read";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("nested deeper than 64"));
  }
  // Objects count as arrays do.
  std::string objects;
  for (int i = 0; i <= kMaxJsonDepth; ++i) objects += "{\"a\":";
  objects += "1" + std::string(std::size_t(kMaxJsonDepth) + 1, '}');
  EXPECT_THROW(parse_json(objects, "test"), InputError);
}

TEST(InputFile, BracketsInStringsAreNotNesting) {
  const std::string brackets(1000, '[');
  const auto j = parse_json("{\"a\": \"" + brackets + "\", \"b\": \"\\\"[[[\"}", "test");
  EXPECT_EQ(j.at("a").get<std::string>(), brackets);
  EXPECT_EQ(j.at("b").get<std::string>(), "\"[[[");
  // An escaped backslash ends its escape: the quote after it closes the string, the brackets after it nest.
  EXPECT_THROW(parse_json("[\"\\\\\"" + std::string(100, '[') + std::string(100, ']') + "]", "test"), InputError);
}

TEST(InputFile, LargeJsonParsesInLinearTime) {
  // A camera path's worth of keyframes, 10 MB: beyond reach of the callback-limited parser, whose cost grew with the
  // square of the size.
  std::string big = "{\"keyframes\": [";
  for (int i = 0; i < 240000; ++i) big += std::string(i ? "," : "") + "{\"origin\": [1.5, 2.5, 3.5], \"fov\": 40}";
  big += "]}";
  const auto start = std::chrono::steady_clock::now();
  const auto j = parse_json(big, "test");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(j.at("keyframes").size(), 240000u);
  EXPECT_LT(seconds, 5.0);
}

}  // namespace
}  // namespace clr::test
