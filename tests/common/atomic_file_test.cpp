// Outputs replace regular files atomically and never replace anything else (a device, a FIFO, a link).
#include "common/atomic_file.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "common/error.hpp"

namespace clr {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class AtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("clr_atomic_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  // Files in `dir` other than `keep`: a leftover temporary shows up here.
  std::size_t others(const fs::path& keep) const {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) n += e.path() != keep;
    return n;
  }
  fs::path dir;
};

TEST_F(AtomicFile, CreatesAndReplacesRegularFiles) {
  const fs::path p = dir / "sub" / "out.txt";
  write_text_atomically(p, "first");
  EXPECT_EQ(read(p), "first");
  write_text_atomically(p, "second");
  EXPECT_EQ(read(p), "second");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "sub"), fs::directory_iterator()), 1);
}

// A valid name one byte short of NAME_MAX: the temporary beside it must fit too.
TEST_F(AtomicFile, ALongestNameStillWrites) {
  const fs::path target = dir / std::string(254, 'n');
  write_text_atomically(target, "long");
  EXPECT_EQ(read(target), "long");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1) << "a temporary was left";
}

TEST_F(AtomicFile, FailedWriteLeavesTheOldFileAndNoTemporary) {
  const fs::path p = dir / "out.txt";
  write_text_atomically(p, "old");
  EXPECT_THROW(write_atomically(p,
                                [](const fs::path& tmp) {
                                  std::ofstream(tmp) << "partial";
                                  throw std::runtime_error("disk full");
                                }),
               std::runtime_error);
  EXPECT_EQ(read(p), "old");
  EXPECT_EQ(others(p), 0u);
}

TEST_F(AtomicFile, DevNullStaysADevice) {
  ASSERT_TRUE(fs::is_character_file("/dev/null")) << "this test needs /dev/null";
  const auto temporaries = [] {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(fs::temp_directory_path()))
      n += e.path().filename().string().starts_with("clradiosity-" + std::to_string(::getpid()));
    return n;
  };
  write_text_atomically("/dev/null", "discarded");
  EXPECT_TRUE(fs::is_character_file("/dev/null")) << "/dev/null was replaced";
  EXPECT_EQ(temporaries(), 0u);
  // A failed write through a device leaves no temporary behind either.
  EXPECT_THROW(write_atomically("/dev/null", [](const fs::path&) { throw std::runtime_error("no"); }),
               std::runtime_error);
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_EQ(temporaries(), 0u);
}

TEST_F(AtomicFile, FifoIsWrittenThroughNotReplaced) {
  const fs::path fifo = dir / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = read(fifo); });  // opening blocks until the writer opens its end
  try {
    write_text_atomically(fifo, "through the pipe");
  } catch (...) {
    ::close(::open(fifo.c_str(), O_WRONLY | O_NONBLOCK));  // releases the reader, so a failure cannot hang
    reader.join();
    throw;
  }
  reader.join();
  EXPECT_EQ(received, "through the pipe");
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(others(fifo), 0u);
}

TEST_F(AtomicFile, SymlinkKeepsPointingAtTheReplacedFile) {
  const fs::path target = dir / "target.txt", link = dir / "link.txt";
  write_text_atomically(target, "old");
  fs::create_symlink(target, link);
  write_text_atomically(link, "new");
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(read(target), "new");
}

TEST_F(AtomicFile, DirectoryIsBadInput) {
  EXPECT_THROW(write_text_atomically(dir, "x"), InputError);
  EXPECT_TRUE(fs::is_directory(dir));
}

}  // namespace
}  // namespace clr
