#pragma once
// The scratch folder of a CLI test (removed after it; named by the fixture and the process, so parallel ctest
// processes do not meet) holding `small.json`: a network small enough that a CLI run takes seconds, with every part
// of the encoder. Fixtures patch it (a JSON merge patch) where they need other logging or checkpointing.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "cl/device.hpp"

namespace clr::test {

class CliRunDir : public ::testing::Test {
 protected:
  CliRunDir(std::string name, nlohmann::json patch = nlohmann::json::object())
      : name_(std::move(name)), patch_(std::move(patch)) {}

  void SetUp() override {
    if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL device";
    dir = std::filesystem::temp_directory_path() / ("clr_" + name_ + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    nlohmann::json small = {
        {"batch", 256},
        {"log_every", 5},
        {"network",
         {{"width", 32}, {"hidden_layers", 2}, {"encoder", {{"grid", {{"levels", 4}, {"log2_table", 12}}}}}}}};
    small.merge_patch(patch_);
    config = (dir / "small.json").string();
    std::ofstream(config) << small.dump();
  }
  void TearDown() override { std::filesystem::remove_all(dir); }

  std::filesystem::path dir;
  std::string config;  // the path of small.json

 private:
  std::string name_;
  nlohmann::json patch_;
};

// The number of lines in a file (log.csv rows, say); 0 when it cannot be read.
inline std::size_t lines_in(const std::filesystem::path& p) {
  std::ifstream in(p);
  return std::size_t(std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n'));
}

}  // namespace clr::test
