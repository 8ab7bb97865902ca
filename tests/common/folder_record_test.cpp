// A folder's record of the settings its contents were made with: written by the first run, compared by every rerun,
// and never made up for contents that were made without one.
#include "common/folder_record.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>

#include "common/error.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class FolderRecord : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  const fs::path dir = fs::temp_directory_path() / ("clr_folder_record_" + std::to_string(::getpid()));
  const nlohmann::json record = {{"spp", 4}, {"width", 64}};
  const std::map<std::string, std::string> options = {{"spp", "--spp"}, {"width", "--width"}};
};

TEST_F(FolderRecord, WrittenFirstThenCompared) {
  require_same_record(dir / "frames.json", record, "frames", options);
  EXPECT_TRUE(fs::exists(dir / "frames.json"));
  EXPECT_NO_THROW(require_same_record(dir / "frames.json", record, "frames", options, "frames (frame_00000.exr)"));
  try {
    require_same_record(dir / "frames.json", {{"spp", 8}, {"width", 64}}, "frames", options);
    ADD_FAILURE() << "other settings were accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("--spp was 4, now 8"));
  }
}

TEST_F(FolderRecord, ContentWithoutItsRecordIsRefused) {
  for (const char* content : {"frames (frame_00003.exr)", "rows (results.csv)"}) {
    try {
      require_same_record(dir / "record.json", record, "things", options, content);
      ADD_FAILURE() << content << " without a record was adopted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(std::string("holds ") + content + " but no record"));
      EXPECT_THAT(e.what(), HasSubstr("record.json"));
    }
    EXPECT_FALSE(fs::exists(dir / "record.json")) << "no record is made up for content made without one";
  }
}

// Records are files: one that is a FIFO is neither read (it would block) nor written through.
TEST_F(FolderRecord, RecordsAreNeverWrittenThroughAFifo) {
  ASSERT_EQ(::mkfifo((dir / "fifo.json").c_str(), 0600), 0);
  EXPECT_THROW(require_same_record(dir / "fifo.json", record, "frames", options), InputError);
  EXPECT_TRUE(fs::is_fifo(dir / "fifo.json"));
}

}  // namespace
}  // namespace clr::test
