// `clradiosity sweep` as a user runs it, on the bundled Cornell box at 16×16 with a tiny network: the rows, the
// tables and the figures it leaves, a rerun that trains nothing again, Ctrl-C and a rerun that completes, and
// bad options.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>
#include <tuple>

#include "cl/device.hpp"
#include "image/image.hpp"
#include "support/background_cli.hpp"
#include "support/cli_run_dir.hpp"
#include "support/run_cli.hpp"
#include "sweep/results_csv.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kBox = (fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml").string();

class SweepCli : public CliRunDir {
 protected:
  SweepCli() : CliRunDir("sweep_cli") {}
  void SetUp() override {
    CliRunDir::SetUp();
    // Small everything: the budgets are seconds, the residual's estimate coarse; what is tested is the sweep.
    common = " --width 16 --height 16 --spp 4 --reference-spp 64 --residual-points 256 --residual-samples 4 --config " +
             config;
  }

  // The sweep's arguments for SWEEP_DIR `out`: both methods, N = 4, one seed.
  std::string args(const fs::path& out, const std::string& minutes) const {
    return "sweep " + kBox + " -o " + out.string() + " --minutes " + minutes + " --methods nr,isnr-ikl" + common;
  }

  std::string common;
};

// Every number a row carries is finite where the row's kind has it.
void expect_complete(const sweep::Row& r) {
  EXPECT_TRUE(std::isfinite(r.mape) && std::isfinite(r.mse) && std::isfinite(r.relmse)) << r.key();
  EXPECT_GT(r.seconds, 0) << r.key();
  EXPECT_GT(r.spp, 0) << r.key();
  if (r.kind == sweep::RowKind::Model) {
    EXPECT_TRUE(std::isfinite(r.residual) && std::isfinite(r.residual_se)) << r.key();
    EXPECT_GT(r.steps, 0u) << r.key();
    EXPECT_GT(r.peak_device_mib, 0) << r.key();
    EXPECT_GT(r.render_seconds, 0) << r.key();
  }
}

// As the sweep looks for it: the python3 on PATH, else Debian's.
bool matplotlib_present() {
  return std::system("python3 -c 'import matplotlib' >/dev/null 2>&1") == 0 ||
         std::system("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1") == 0;
}

TEST_F(SweepCli, TrainsEachConfigurationOnceAndRerunsNothing) {
  const fs::path out = dir / "sweep";
  const auto start = std::chrono::steady_clock::now();
  auto r = run_cli(args(out, "0.02,0.01"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  RecordProperty("seconds",
                 std::to_string(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()));
  EXPECT_THAT(r.out, HasSubstr("no --reference: path-tracing one"));
  const auto rows = sweep::read_results(out / "results.csv");

  // methods × N × seeds × budgets rows at the budgets, NR's rows at each ISNR row's step count, and the path
  // tracer's: one per budget, its timing pass and the doublings before the first budget (the models here are far
  // worse than it: none after the budgets).
  std::map<std::string, std::vector<const sweep::Row*>> budget_rows;
  std::size_t steps_rows = 0, pt_budget = 0, pt_progress = 0;
  for (const auto& row : rows) {
    expect_complete(row);
    if (row.kind == sweep::RowKind::Model && row.point == sweep::Point::Budget) budget_rows[row.method].push_back(&row);
    if (row.kind == sweep::RowKind::Model && row.point == sweep::Point::Steps) ++steps_rows;
    if (row.kind == sweep::RowKind::PathTracing) ++(row.point == sweep::Point::Budget ? pt_budget : pt_progress);
  }
  ASSERT_EQ(budget_rows.size(), 2u);
  for (const auto& [method, list] : budget_rows) {
    ASSERT_EQ(list.size(), 2u) << method;
    // One run per configuration: the larger budget's snapshot is the same run further on.
    EXPECT_EQ(list[0]->budget_minutes, 0.01) << method;
    EXPECT_LT(list[0]->steps, list[1]->steps) << method;
    for (const auto* b : list) {
      EXPECT_GE(b->seconds, b->budget_minutes * 60) << method;
      EXPECT_LT(b->seconds, b->budget_minutes * 60 + 0.5) << method << ": rendering counted as training?";
    }
    EXPECT_EQ(fs::exists(out / "runs" / (method + "-n4-seed1") / "0.01min" / "model.clr"), true);
  }
  EXPECT_EQ(steps_rows, 2u);
  for (const auto& row : rows)
    if (row.point == sweep::Point::Steps) {
      EXPECT_EQ(row.method, "nr");
      EXPECT_TRUE(std::any_of(rows.begin(), rows.end(),
                              [&](const sweep::Row& o) { return o.method == "isnr-ikl" && o.steps == row.steps; }));
      EXPECT_LT(row.seconds, 0.02 * 60) << "NR reaches ISNR's step count sooner";
    }
  EXPECT_EQ(pt_budget, 2u);
  EXPECT_GE(pt_progress, 1u);
  int first_budget_spp = 1 << 30;
  for (const auto& row : rows)
    if (row.kind == sweep::RowKind::PathTracing && row.point == sweep::Point::Budget)
      first_budget_spp = std::min(first_budget_spp, row.spp);
  for (const auto& row : rows)
    if (row.kind == sweep::RowKind::PathTracing && row.point == sweep::Point::Progress) {
      EXPECT_LT(row.spp, first_budget_spp);
    }
  EXPECT_EQ(rows.size(), 4 + steps_rows + pt_budget + pt_progress);

  std::ifstream tables(out / "tables.md");
  const std::string md{std::istreambuf_iterator<char>(tables), std::istreambuf_iterator<char>()};
  for (const char* part : {"Table 1 — equal steps", "Table 2 — equal time", "Table 3 — residual", "equal error"})
    EXPECT_THAT(md, HasSubstr(part));
  if (matplotlib_present()) {
    EXPECT_TRUE(fs::exists(out / "mape_vs_time.png"));
    EXPECT_TRUE(fs::exists(out / "strip.png"));
  } else {
    EXPECT_THAT(r.out, HasSubstr("python3-matplotlib is missing"));
  }

  // A rerun keeps every row and trains nothing: the runs' checkpoints stay as they were.
  const auto checkpoint = out / "runs" / "nr-n4-seed1" / "train" / "model.clr";
  const auto written = fs::last_write_time(checkpoint);
  r = run_cli(args(out, "0.01,0.02"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("nr-n4-seed1: every row done, reused"));
  EXPECT_THAT(r.out, HasSubstr("isnr-ikl-n4-seed1: every row done, reused"));
  EXPECT_THAT(r.out, ::testing::Not(HasSubstr("training to")));
  EXPECT_EQ(fs::last_write_time(checkpoint), written);
  const auto again = sweep::read_results(out / "results.csv");
  ASSERT_EQ(again.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(again[i].mape, rows[i].mape);

  // A rerun that would measure rows another way is refused before any work, naming what changed; budgets and
  // methods may grow (they only add rows).
  const std::string reference = (dir / "other_reference.exr").string();
  ASSERT_EQ(run_cli("reference " + kBox + " --width 16 --height 16 --spp 1 -o " + reference).exit_code, 0);
  for (const auto& [from, to, culprit] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"--width 16", "--width 8", "--width"},
           {"--spp 4", "--spp 8", "--spp"},
           {"--residual-samples 4", "--residual-samples 8", "--residual-samples"},
           {"--reference-spp 64", "--reference " + reference, "--reference"}}) {
    std::string changed = args(out, "0.01");
    changed.replace(changed.find(from), from.size(), to);
    r = run_cli(changed);
    EXPECT_EQ(r.exit_code, 2) << to << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr(culprit)) << to;
    EXPECT_THAT(r.err, HasSubstr(out.string())) << to;
    EXPECT_EQ(sweep::read_results(out / "results.csv").size(), rows.size()) << to;
  }
}

TEST_F(SweepCli, InterruptKeepsFinishedRowsAndARerunCompletes) {
  const fs::path out = dir / "sweep";
  const pid_t pid = spawn_cli(words(args(out, "0.01,0.03")));
  ASSERT_GE(pid, 0);
  // ISNR trains first and its rows appear when its run is done; NR then trains for 1.8 s. Ctrl-C once NR's log
  // shows 0.9 s of training lands in it, past its first budget's snapshot and half way to its last.
  const fs::path nr_log = out / "runs" / "nr-n4-seed1" / "train" / "log.csv";
  const auto nr_seconds = [&] {
    std::ifstream in(nr_log);
    std::string line, last;
    while (std::getline(in, line)) last = line;
    const auto comma = last.find(',');
    return comma == std::string::npos || !std::isdigit(static_cast<unsigned char>(last[0]))
               ? 0.0
               : std::stod(last.substr(comma + 1));
  };
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (nr_seconds() < 0.9 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 130) << "a clean stop by SIGINT exits 128 + 2";
  const auto before = sweep::read_results(out / "results.csv");
  ASSERT_EQ(before.size(), 2u) << "ISNR's two rows, none of NR's";
  for (const auto& row : before) expect_complete(row);

  auto args =
      std::string("sweep " + kBox + " -o " + out.string() + " --minutes 0.01,0.03 --methods nr,isnr-ikl") + common;
  const auto r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("isnr-ikl-n4-seed1: every row done, reused"));
  EXPECT_THAT(r.out, HasSubstr("nr-n4-seed1: resuming at"));
  const auto after = sweep::read_results(out / "results.csv");
  ASSERT_GE(after.size(), before.size());
  for (std::size_t i = 0; i < before.size(); ++i) EXPECT_EQ(after[i].key(), before[i].key());
  std::size_t budget_rows = 0;
  for (const auto& row : after) {
    expect_complete(row);
    if (row.kind == sweep::RowKind::Model && row.point == sweep::Point::Budget) {
      ++budget_rows;
      EXPECT_LT(row.seconds, row.budget_minutes * 60 + 0.5) << row.key();
    }
  }
  EXPECT_EQ(budget_rows, 4u);
  // The budget counts the training of both sessions: NR's second session trained the 0.9 s that were left, not
  // another 1.8 s (its snapshots would not show it: they are taken at the total's budgets either way).
  EXPECT_LT(nr_seconds(), 0.03 * 60 + 0.5);
  EXPECT_TRUE(std::any_of(after.begin(), after.end(), [](const sweep::Row& row) {
    return row.kind == sweep::RowKind::PathTracing && row.point == sweep::Point::Budget;
  }));
}

TEST_F(SweepCli, BadOptionsExitTwoNamingTheCulprit) {
  const std::string out = " -o " + (dir / "bad").string();
  image::write_exr(dir / "small.exr", image::Image(7, 7));
  fs::create_directories(dir / "damaged");
  std::ofstream(dir / "damaged" / "results.csv") << "not,a,sweep\n";
  // Rows without the record of what they were made with (sweep.json): never adopted under the settings given now.
  fs::create_directories(dir / "unrecorded");
  sweep::write_results(dir / "unrecorded" / "results.csv", {});
  const std::pair<std::string, std::string> cases[] = {
      {"sweep " + kBox + out + " --methods nr,foo", "foo"},
      {"sweep " + (dir / "missing.xml").string() + out, "missing.xml"},
      {"sweep " + kBox + out + " --reference " + (dir / "none.exr").string(), "none.exr"},
      {"sweep " + kBox + out + " --width 16 --height 16 --reference " + (dir / "small.exr").string(), "small.exr"},
      {"sweep " + kBox + out + " --minutes 0", "--minutes"},
      {"sweep " + kBox + out + " --minutes 1,nan", "--minutes"},
      {"sweep " + kBox + out + " --samples 0", "--samples"},
      {"sweep " + kBox + out + " --seeds 0", "--seeds"},
      {"sweep " + kBox + out + " --device nosuch", "nosuch"},
      {"sweep " + kBox, "--output"},
      {"sweep " + kBox + " -o " + (dir / "damaged").string(), "results.csv"},
      {"sweep " + kBox + " -o " + (dir / "unrecorded").string(), "holds rows (results.csv) but no record"},
  };
  for (const auto& [args, culprit] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr(culprit)) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "bad" / "results.csv"));
  EXPECT_FALSE(fs::exists(dir / "unrecorded" / "sweep.json")) << "a record was made up for rows made without one";
}

}  // namespace
}  // namespace clr::test
