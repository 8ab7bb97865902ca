#pragma once
// The shared scenes (CMake cache variable CLR_SHARED_SCENES, default ../shared/scenes) are never part of this
// repository: a test that needs one skips where it is absent, naming the path and how to point the build at it.
#include <gtest/gtest.h>

#include <filesystem>

namespace clr::test {

inline std::filesystem::path shared_scenes() { return CLR_SHARED_SCENES; }

}  // namespace clr::test

// Skips the calling test unless `where` (a file or folder under the shared scenes) exists.
#define CLR_REQUIRE_SHARED(where)                                      \
  if (!std::filesystem::exists(where))                                 \
  GTEST_SKIP() << "skipped: " << std::filesystem::path(where).string() \
               << " is absent (the shared scenes; configure with -DCLR_SHARED_SCENES=FOLDER to point at them)"
