#pragma once
// A temporary folder for scene files written by a test, removed afterwards.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace clr::test {

class SceneFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() / ("clr_scene_" + std::string(info->test_suite_name()) + "_" +
                                                     info->name() + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path write(const std::string& name, const std::string& text) const {
    const auto p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  // A scene file of the given version holding `body`.
  std::filesystem::path scene(const std::string& body, const std::string& version = "3.0.0",
                              const std::string& name = "scene.xml") const {
    return write(name, "<scene version=\"" + version + "\">\n" + body + "\n</scene>\n");
  }

  std::filesystem::path dir_;
};

}  // namespace clr::test
