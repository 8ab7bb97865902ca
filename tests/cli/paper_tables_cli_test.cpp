// bench/paper_tables.sh at a tiny scale: it drives train, reference and compare by their printed lines and log.csv's
// columns, so a change to any of them that the script does not follow fails here rather than in an hours-long run.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "support/cli_run_dir.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

std::string text_of(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class PaperTablesCli : public CliRunDir {
 protected:
  PaperTablesCli() : CliRunDir("paper_tables_cli") {}
  // Runs the script on the bundled Cornell box; its stdout in `out`, the exit status returned.
  int run_script(std::string& out) {
    const fs::path log = dir / "script.log";
    const std::string command = "env CLRADIOSITY='" + std::string(CLR_CLI_PATH) +
                                "' STEPS=20 EVAL_EVERY=10 EVAL_LONG_SIDE=32 REF_SPP=16 TABLES='1 2' PRESET= "
                                "TRAIN_FLAGS='--config " +
                                config + "' bash '" + CLR_SOURCE_DIR + "/bench/paper_tables.sh' '" +
                                (dir / "out").string() + "' '" + CLR_SOURCE_DIR + "/scenes/cornell-box.xml' >'" +
                                log.string() + "' 2>&1";
    const int status = std::system(command.c_str());
    out = text_of(log);
    return status;
  }
};

TEST_F(PaperTablesCli, WritesTheTablesAndKeepsWhatItRan) {
  if (std::system("python3 -c 'import json' >/dev/null 2>&1") != 0) GTEST_SKIP() << "no python3";
  std::string out;
  ASSERT_EQ(run_script(out), 0) << out;
  const std::string tables = text_of(dir / "out" / "tables.md");
  for (const char* part : {"#### Table 1 (N = 4", "#### Table 2 (N = 32", "#### Table 4", "#### Time to quality",
                           "| NR | 20 |", "| ISNR (KL) | 20 |", "| ISNR (IKL) | 20 |", "Path tracer (rendering"})
    EXPECT_THAT(tables, HasSubstr(part)) << tables;
  EXPECT_THAT(text_of(dir / "out" / "cornell-box-curves.svg"), HasSubstr("<polyline"));
  // Every run logged its evaluations and its memory (a renamed line in train's output would leave it null).
  for (const char* run : {"t1-nr", "t1-isnr-kl", "t1-isnr-ikl", "t2-nr", "t2-isnr-ikl"}) {
    const fs::path folder = dir / "out" / "runs" / "cornell-box" / run;
    EXPECT_THAT(text_of(folder / "run.json"), Not(HasSubstr("null"))) << run;
    EXPECT_TRUE(fs::exists(folder / "convergence.svg")) << run;
  }
  // A rerun trains nothing again.
  ASSERT_EQ(run_script(out), 0) << out;
  std::size_t kept = 0;
  for (auto at = out.find("done, kept"); at != std::string::npos; at = out.find("done, kept", at + 1)) ++kept;
  EXPECT_EQ(kept, 5u) << out;
  EXPECT_THAT(out, Not(HasSubstr("training")));
  EXPECT_THAT(out, Not(HasSubstr("reference 32x32"))) << "the reference is cached";
}

// The shell's single quotes around `text`, with its own quotes escaped.
std::string shell_quoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Names are data: a scene whose name holds a quote (once pasted into Python code, where a crafted one ran as code)
// is tabled like any other; a bad TABLES is refused before any reference is rendered.
TEST_F(PaperTablesCli, NamesAreDataAndBadTablesAreRefusedFirst) {
  if (std::system("python3 -c 'import json' >/dev/null 2>&1") != 0) GTEST_SKIP() << "no python3";
  const std::string script = std::string(CLR_SOURCE_DIR) + "/bench/paper_tables.sh";
  const fs::path odd = dir / "scenes" / "it's'];open('pwned','w')#.xml";
  fs::create_directories(odd.parent_path());
  fs::copy_file(fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml", odd);
  const auto run = [&](const std::string& tables, const fs::path& out) {
    const std::string command = "cd " + shell_quoted(dir.string()) +
                                " && env CLRADIOSITY=" + shell_quoted(CLR_CLI_PATH) +
                                " STEPS=10 EVAL_EVERY=10 EVAL_LONG_SIDE=32 REF_SPP=16 TABLES=" + shell_quoted(tables) +
                                " PRESET= TRAIN_FLAGS=" + shell_quoted("--config " + config) + " bash " +
                                shell_quoted(script) + " " + shell_quoted(out.string()) + " " +
                                shell_quoted(odd.string()) + " >" + shell_quoted((dir / "odd.log").string()) + " 2>&1";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(run("1 3", dir / "bad"), 2) << text_of(dir / "odd.log");
  EXPECT_THAT(text_of(dir / "odd.log"), HasSubstr("TABLES: '3' is not 1 or 2"));
  EXPECT_FALSE(fs::exists(dir / "bad")) << "refused before any reference was rendered";
  ASSERT_EQ(run("1", dir / "good"), 0) << text_of(dir / "odd.log");
  EXPECT_FALSE(fs::exists(dir / "pwned")) << "a scene's name ran as Python code";
  const std::string tables = text_of(dir / "good" / "tables.md");
  EXPECT_THAT(tables, HasSubstr("| NR | 10 |")) << tables;
  const auto record = nlohmann::json::parse(text_of(dir / "good" / "runs" / odd.stem().string() / "scene.json"));
  EXPECT_EQ(record.at("scene").get<std::string>(), odd.string());
}

}  // namespace
}  // namespace clr::test
