// The command-line habits Mitsuba and pbrt users bring (docs/cli.md): an image output's format from its extension,
// -D key=value for the scene's parameters, reference's samples per pixel from the scene's sampler,
// -q/--quiet, the metadata of EXRs, --sensor.
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfStringAttribute.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "image/image.hpp"
#include "support/background_cli.hpp"
#include "support/cli_run_dir.hpp"
#include "support/run_cli.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kBox = (fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml").string();

class HabitsCli : public CliRunDir {
 protected:
  HabitsCli() : CliRunDir("habits_cli") {}
  fs::path train(const std::string& name = "run") {
    const fs::path run = dir / name;
    const auto r = run_cli("train " + kBox + " --steps 5 --config " + config + " -o " + run.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return run;
  }
};

// The first bytes: EXR's magic number, or PNG's signature.
std::string kind(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  char b[4] = {};
  in.read(b, 4);
  if (std::string(b, 4) == std::string("\x76\x2f\x31\x01", 4)) return "exr";
  if (std::string(b + 1, 3) == "PNG") return "png";
  return fs::exists(p) ? "other" : "missing";
}

void expect_refused(const std::string& args, const std::string& option) {
  const auto r = run_cli(args);
  EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
  EXPECT_THAT(r.err, HasSubstr(option + " ")) << args;
  EXPECT_THAT(r.err, HasSubstr("the extension names the image format")) << args;
}

TEST_F(HabitsCli, ReferencePicksItsFormatFromTheExtension) {
  const std::string base = "reference " + kBox + " --spp 1 --width 8 --height 8 -o ";
  for (const auto& [name, expected] : {std::pair{"a.exr", "exr"}, {"b.png", "png"}, {"c.PNG", "png"}}) {
    const auto r = run_cli(base + (dir / name).string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(kind(dir / name), expected) << name;
  }
  for (const char* name : {"d.jpg", "e", "f.exr.tmp"}) {
    expect_refused(base + (dir / name).string(), "-o");
    EXPECT_EQ(kind(dir / name), "missing") << name;
  }
  // Devices have no extension: written through, as EXR.
  EXPECT_EQ(run_cli(base + "/dev/null").exit_code, 0);
}

TEST_F(HabitsCli, EveryImageOutputIsCheckedBeforeTheWork) {
  const fs::path run = train();
  const std::string render = "render " + kBox + " --model " + run.string() + " --width 8 --height 8 ";
  EXPECT_EQ(run_cli(render + "-o " + (dir / "r.png").string()).exit_code, 0);
  EXPECT_EQ(kind(dir / "r.png"), "png");
  EXPECT_EQ(run_cli(render + "-o " + (dir / "r.exr").string()).exit_code, 0);
  EXPECT_EQ(kind(dir / "r.exr"), "exr");
  // Before the model is read: a run that does not exist is not what the line names.
  expect_refused("render " + kBox + " --model " + (dir / "none").string() + " -o " + (dir / "r.tif").string(), "-o");
  expect_refused(render + "-o " + (dir / "s.exr").string() + " --png " + (dir / "s.exr").string(), "--png");
  expect_refused(render + "-o " + (dir / "t.exr").string() + " --reference " + (dir / "r.exr").string() +
                     " --error-map " + (dir / "t.exr").string(),
                 "--error-map");
  EXPECT_EQ(kind(dir / "s.exr"), "missing");
  EXPECT_EQ(kind(dir / "t.exr"), "missing");

  const std::string guide =
      "guide " + kBox + " --model " + run.string() + " --pixel 4,4 --width 8 --height 8 " + "--resolution 8 -o ";
  EXPECT_EQ(run_cli(guide + (dir / "g.exr").string()).exit_code, 0);
  EXPECT_EQ(kind(dir / "g.exr"), "exr");
  expect_refused(guide + (dir / "g.bmp").string(), "-o");
  expect_refused(guide + (dir / "h.png").string() + " --exr " + (dir / "h.png").string(), "--exr");
  expect_refused("compare " + (dir / "r.exr").string() + " " + (dir / "r.exr").string() + " --error-map " +
                     (dir / "m.jpg").string(),
                 "--error-map");
  expect_refused("train " + kBox + " --steps 1 --config " + config + " --preview " + (dir / "p.exr").string() + " -o " +
                     (dir / "run2").string(),
                 "--preview");
  EXPECT_FALSE(fs::exists(dir / "run2" / "model.clr")) << "trained before refusing --preview";
}

// The bundled Cornell box's film is $res × $res (<default name="res" value="128"/>).
TEST_F(HabitsCli, SceneParametersFillTheSceneAndItsDigest) {
  auto r = run_cli("reference " + kBox + " --spp 1 -D res=16 -o " + (dir / "d.exr").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(image::read_exr(dir / "d.exr").width, 16);
  r = run_cli("reference " + kBox + " --spp 1 -D res -o " + (dir / "e.exr").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("'res' is not key=value"));

  const fs::path run = dir / "run";
  r = run_cli("train " + kBox + " --steps 2 --config " + config + " -D res=24 -o " + run.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Another parameter value is another scene, as another file would be: refused naming the parameters.
  r = run_cli("render " + kBox + " --model " + run.string() + " -o " + (dir / "f.exr").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("the parameters differ (-D res=24 then, none now)"));
  r = run_cli("render " + kBox + " -D res=24 --model " + run.string() + " -o " + (dir / "f.exr").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(image::read_exr(dir / "f.exr").width, 24);
  // A value equal to the file's own <default> changes nothing: the run of the plain scene accepts it.
  const fs::path plain = train("plain");
  r = run_cli("render " + kBox + " -D res=128 --model " + plain.string() + " --width 8 --height 8 -o " +
              (dir / "g.exr").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// `reference` without --spp takes the sensor's <sampler> sample_count, as mitsuba does (and -D fills it there).
TEST_F(HabitsCli, ReferenceTakesTheSamplersCount) {
  std::ifstream in(kBox);
  std::stringstream text;
  text << in.rdbuf();
  std::string xml = text.str();
  const auto sensor = xml.find('>', xml.find("<sensor"));
  ASSERT_NE(sensor, std::string::npos);
  xml.insert(sensor + 1, R"(<sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>)");
  xml.insert(xml.find('>', xml.find("<scene")) + 1, R"(<default name="spp" value="3"/>)");
  const fs::path scene = dir / "sampled.xml";
  std::ofstream(scene) << xml;
  const std::string base = " --width 4 --height 4 -o " + (dir / "s.exr").string();
  auto r = run_cli("reference " + scene.string() + base);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr(", 3 spp,"));
  r = run_cli("reference " + scene.string() + " -D spp=5" + base);
  EXPECT_THAT(r.out, HasSubstr(", 5 spp,"));
  r = run_cli("reference " + scene.string() + " --spp 2" + base);
  EXPECT_THAT(r.out, HasSubstr(", 2 spp,")) << "--spp wins over the scene";
  r = run_cli("reference " + scene.string() + " -D spp=0" + base);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("sampler asks for 0"));
  // A scene without a sampler still needs --spp, and says so.
  r = run_cli("reference " + kBox + base);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("--spp: give the samples per pixel"));
}

// The bundled box with a second sensor after its first: a 24 × 16 film elsewhere, its own sampler (2 spp).
fs::path two_sensor_box(const fs::path& dir) {
  std::ifstream in(kBox);
  std::stringstream text;
  text << in.rdbuf();
  std::string xml = text.str();
  const auto end = xml.find("</sensor>") + std::string("</sensor>").size();
  xml.insert(end, R"(<sensor type="perspective"><float name="fov" value="40"/>
      <transform name="to_world"><lookat origin="0.5, 1.5, 4" target="0, 0.8, 0" up="0, 1, 0"/></transform>
      <sampler type="independent"><integer name="sample_count" value="2"/></sampler>
      <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/></film></sensor>)");
  const fs::path scene = dir / "two-sensors.xml";
  std::ofstream(scene) << xml;
  return scene;
}

// --sensor INDEX, Mitsuba's sensor index: every command that renders a view takes the sensor it names, with that
// sensor's film and sampler; one the scene lacks exits 2 naming how many it has.
TEST_F(HabitsCli, SensorPicksTheView) {
  const std::string scene = two_sensor_box(dir).string();
  auto r = run_cli("reference " + scene + " --spp 1 -D res=32 -o " + (dir / "a.exr").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("32x32, 1 spp"));
  r = run_cli("reference " + scene + " --sensor 1 -o " + (dir / "b.exr").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("24x16, 2 spp")) << "the second sensor's film and sampler";
  for (const std::string& args : {"reference " + scene + " --sensor 2 --spp 1 -o " + (dir / "c.exr").string(),
                                  "reference " + kBox + " --sensor 1 --spp 1 -o " + (dir / "c.exr").string()}) {
    r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_THAT(r.err, HasSubstr("--sensor ")) << args;
    EXPECT_THAT(r.err, HasSubstr(args.find(kBox) != std::string::npos ? "has 1 sensor" : "has 2 sensors (0 to 1)"));
  }
  EXPECT_FALSE(fs::exists(dir / "c.exr"));

  // Training evaluates and previews through the sensor it is given; render and guide take theirs.
  const fs::path run = dir / "run";
  r = run_cli("train " + scene + " --sensor 1 --steps 4 --config " + config + " --reference " +
              (dir / "b.exr").string() + " -o " + run.string());
  ASSERT_EQ(r.exit_code, 0) << r.err << "\nthe 24 × 16 reference fits the second sensor's film only";
  r = run_cli("render " + scene + " --sensor 1 --model " + run.string() + " --spp 1 -o " + (dir / "r.exr").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rendered = image::read_exr(dir / "r.exr");
  EXPECT_EQ(rendered.width, 24);
  EXPECT_EQ(rendered.height, 16);
  r = run_cli("guide " + scene + " --sensor 1 --model " + run.string() + " --pixel 100,5 --resolution 8 -o " +
              (dir / "g.png").string());
  EXPECT_EQ(r.exit_code, 2) << "pixel 100 lies outside the second sensor's 24-pixel film";
  r = run_cli("guide " + scene + " --model " + run.string() + " --pixel 100,5 --resolution 8 -o " +
              (dir / "g.png").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// A reference is judged by what its header records: one path-traced from another sensor or another scene (other
// files, other -D parameters) is refused by every command that measures against it; a resumed run's evaluations
// keep their sensor; one holding less than the whole transport gets a warning.
TEST_F(HabitsCli, AReferenceOfAnotherViewOrSceneIsRefused) {
  const std::string scene = two_sensor_box(dir).string(), other = (dir / "other.exr").string(),
                    sensor1 = (dir / "sensor1.exr").string(), edited = (dir / "edited.exr").string(),
                    shallow = (dir / "shallow.exr").string(), run = (dir / "run").string();
  ASSERT_EQ(run_cli("reference " + scene + " --sensor 1 --spp 1 --width 24 --height 16 -o " + sensor1).exit_code, 0);
  // The first sensor's film is square: a square reference of the first sensor with other -D parameters.
  ASSERT_EQ(run_cli("reference " + scene + " --spp 1 -D res=16 -o " + edited).exit_code, 0);
  ASSERT_EQ(run_cli("reference " + kBox + " --spp 1 --width 16 --height 16 -o " + other).exit_code, 0);
  ASSERT_EQ(run_cli("reference " + scene + " --spp 1 --width 16 --height 16 --max-depth 2 -o " + shallow).exit_code, 0);
  const std::string train = "train " + scene + " --steps 2 --config " + config + " ";
  const std::pair<std::string, std::string> refused[] = {
      // sensor 1's image against sensor 0 (it has another aspect; a 3:2 sensor 0 would be the same case)
      {train + "--sensor 0 -D res=24 --reference " + sensor1 + " -o " + run, "another scene"},
      {train + "--reference " + edited + " -o " + run, "another scene"},
      {train + "--reference " + other + " -o " + run, "another scene"},
      {"render " + scene + " --model " + run + " --spp 1 --width 16 --height 16 --reference " + other + " -o " +
           (dir / "r.exr").string(),
       "another scene"}};
  ASSERT_EQ(run_cli(train + "-o " + run).exit_code, 0);
  for (const auto& [command, why] : refused) {
    const auto r = run_cli(command);
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr(why)) << command;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  // The sensor itself: a reference of sensor 1 used where sensor 0 is rendered at the same size.
  const std::string square1 = (dir / "square1.exr").string();
  ASSERT_EQ(run_cli("reference " + scene + " --sensor 1 --spp 1 --width 16 --height 16 -o " + square1).exit_code, 0);
  auto r = run_cli("render " + scene + " --model " + run + " --spp 1 --width 16 --height 16 --reference " + square1 +
                   " -o " + (dir / "r.exr").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("rendered from sensor 1, this command's is 0"));
  // A resumed run measures through the sensor its columns were measured through.
  const std::string evaluated = (dir / "evaluated").string();
  ASSERT_EQ(run_cli(train + "--sensor 1 --reference " + sensor1 + " -o " + evaluated).exit_code, 0);
  r = run_cli("train " + scene + " --resume --steps 4 --sensor 0 --reference " + sensor1 + " -o " + evaluated);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  // A depth-limited reference is measured against, with one warning line.
  r = run_cli(train + "--reference " + shallow + " -o " + (dir / "shallow").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("warning: --reference " + shallow + ": it holds paths of at most 2 segments"));
}

// -q/--quiet, pbrt's: no progress or informational lines on stderr; results on stdout and errors stay.
TEST_F(HabitsCli, QuietLeavesResultsAndErrors) {
  const std::string reference = "reference " + kBox + " --spp 1 --width 4 --height 4 -o " + (dir / "q.exr").string();
  auto r = run_cli(reference);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("reference")) << "without -q the progress line is there";
  r = run_cli(reference + " -q");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.err, "");
  EXPECT_THAT(r.out, HasSubstr("1 spp"));
  const std::string train = "train " + kBox + " --steps 2 --config " + config + " -o ";
  r = run_cli(train + (dir / "loud").string());
  EXPECT_THAT(r.err, HasSubstr("train: "));
  r = run_cli("--quiet " + train + (dir / "quiet").string());
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.err, "");
  EXPECT_THAT(r.out, HasSubstr("model: "));
  r = run_cli(reference + " -q --width 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("--width"));
}

// An EXR's string attribute, "" where it has none.
std::string exr_attribute(const fs::path& file, const std::string& name) {
  Imf::InputFile in(file.c_str());
  const auto* a = in.header().findTypedAttribute<Imf::StringAttribute>(name);
  return a ? a->value() : "";
}

// pbrt and Mitsuba users stop a long reference and continue it: Ctrl-C keeps the finished passes (exit 130), and
// --resume adds only the samples the image lacks, giving the image one longer render gives.
TEST_F(HabitsCli, ReferenceKeepsItsPassesOnCtrlCAndResumes) {
  const std::string base = "reference " + kBox + " --width 24 --height 16 --seed 3 ";
  const fs::path part = dir / "part.exr", whole = dir / "whole.exr";
  ASSERT_EQ(run_cli(base + "--spp 3 -o " + part.string()).exit_code, 0);
  auto r = run_cli(base + "--spp 10 --resume -o " + part.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("10 spp"));
  EXPECT_THAT(r.err, HasSubstr("3 spp so far; adding 7"));
  ASSERT_EQ(run_cli(base + "--spp 10 -o " + whole.string()).exit_code, 0);
  const auto a = image::read_exr(part), b = image::read_exr(whole);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  for (std::size_t i = 0; i < a.rgb.size(); ++i) ASSERT_NEAR(a.rgb[i], b.rgb[i], 1e-6f * (1 + b.rgb[i])) << i;
  EXPECT_EQ(exr_attribute(part, "spp"), "10");
  EXPECT_EQ(exr_attribute(part, "maxDepth"), exr_attribute(whole, "maxDepth"));
  // Enough already: nothing to add, the file untouched.
  const auto written = fs::last_write_time(part);
  r = run_cli(base + "--spp 6 --resume -o " + part.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("already has 10 spp"));
  EXPECT_EQ(fs::last_write_time(part), written);
  // Another render's image is not continued: each setting that decides the samples, named; and only an EXR.
  for (const auto& [settings, named] :
       std::vector<std::pair<std::string, std::string>>{{"--width 24 --height 16 --seed 4", "seed"},
                                                        {"--width 12 --height 8 --seed 3", "size"},
                                                        {"--width 24 --height 16 --seed 3 --max-depth 2", "maxDepth"},
                                                        {"--width 24 --height 16 --seed 3 -D res=64", "sceneDigest"}}) {
    r = run_cli("reference " + kBox + " " + settings + " --spp 12 --resume -o " + part.string());
    EXPECT_EQ(r.exit_code, 2) << settings;
    EXPECT_THAT(r.err, HasSubstr("its " + named + " is")) << settings << "\n" << r.err;
  }
  // The same box with a box pixel filter (the bundled one names none: Mitsuba's gaussian) draws other samples.
  {
    std::ifstream in(kBox);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string film = "<film type=\"hdrfilm\">";
    ASSERT_NE(text.find(film), std::string::npos);
    text.replace(text.find(film), film.size(), film + "<rfilter type=\"box\"/>");
    std::ofstream(dir / "box-filtered.xml") << text;
    r = run_cli("reference " + (dir / "box-filtered.xml").string() +
                " --width 24 --height 16 --seed 3 --spp 12 "
                "--resume -o " +
                part.string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_THAT(r.err, HasSubstr("its pixelFilter is")) << r.err;
  }
  EXPECT_EQ(fs::last_write_time(part), written);
  r = run_cli(base + "--spp 12 --resume -o " + (dir / "p.png").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("must be an .exr"));
  const fs::path model = dir / "model.exr";
  ASSERT_EQ(run_cli("render " + kBox + " --model " + train().string() + " --width 24 --height 16 -o " + model.string())
                .exit_code,
            0);
  r = run_cli(base + "--spp 12 --resume -o " + model.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("is not an image of clradiosity reference")) << r.err;
  // An image of the right render whose pixels or time were edited: a mean of NaN, negative or infinite radiance, or
  // a render time that is none, is not continued.
  {
    std::map<std::string, std::string> attributes;
    const image::Image kept = image::read_exr(part, &attributes);
    const fs::path edited = dir / "edited.exr";
    const auto refused = [&](image::Image img, const std::map<std::string, std::string>& header,
                             const std::string& why) {
      image::write_exr(edited, img, header);
      const auto e = run_cli(base + "--spp 12 --resume -o " + edited.string());
      EXPECT_EQ(e.exit_code, 2) << why << ": " << e.err;
      EXPECT_THAT(e.err, HasSubstr(why));
    };
    for (const float bad : {std::nanf(""), -0.5f, INFINITY}) {
      image::Image img = kept;
      img.rgb[7] = bad;
      refused(img, attributes, "not finite radiances");
    }
    for (const char* time : {"nan", "-3", "inf"}) {
      auto header = attributes;
      header["renderTimeSeconds"] = time;
      refused(kept, header, "no usable spp or time");
    }
  }

  // Ctrl-C during a long render: the finished passes are written (a pass is ~2^22 samples, so wait longer each try
  // until one has ended), the file says how many samples it holds, and --resume continues from there.
  const fs::path stopped = dir / "stopped.exr";
  for (int wait_ms = 2000; wait_ms <= 64000 && !fs::exists(stopped); wait_ms *= 2) {
    const pid_t pid = spawn_cli(words(base + "--spp 16000000 -o " + stopped.string()));
    ASSERT_GE(pid, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
    ::kill(pid, SIGINT);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 130);
  }
  ASSERT_TRUE(fs::exists(stopped));
  const int spp = std::stoi(exr_attribute(stopped, "spp"));
  EXPECT_GT(spp, 0);
  EXPECT_LT(spp, 16000000);
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << "left behind: " << entry.path();
  r = run_cli(base + "--spp " + std::to_string(spp + 2) + " --resume -o " + stopped.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(exr_attribute(stopped, "spp"), std::to_string(spp + 2));
}

// What made an EXR travels in its header, as pbrt records spp and render time.
TEST_F(HabitsCli, ExrsRecordHowTheyWereMade) {
  const fs::path ref = dir / "ref.exr";
  auto r = run_cli("reference " + kBox + " --spp 2 --seed 9 --width 4 --height 4 -o " + ref.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto scene = nlohmann::json::parse(std::ifstream(train() / "scene.json"));
  EXPECT_EQ(exr_attribute(ref, "spp"), "2");
  EXPECT_EQ(exr_attribute(ref, "seed"), "9");
  EXPECT_EQ(exr_attribute(ref, "sceneDigest"), scene.at("digest").get<std::string>());
  EXPECT_THAT(exr_attribute(ref, "commandLine"), HasSubstr("reference " + kBox + " --spp 2 --seed 9"));
  EXPECT_THAT(exr_attribute(ref, "software"), HasSubstr("clradiosity"));
  EXPECT_FALSE(exr_attribute(ref, "renderTimeSeconds").empty());
  EXPECT_EQ(exr_attribute(ref, "steps"), "") << "a path-traced image has no training steps";

  const fs::path img = dir / "model.exr";
  r = run_cli("render " + kBox + " --model " + (dir / "run").string() + " --spp 3 --width 4 --height 4 -o " +
              img.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(exr_attribute(img, "steps"), "5");
  EXPECT_EQ(exr_attribute(img, "spp"), "3");
  EXPECT_EQ(exr_attribute(img, "sceneDigest"), scene.at("digest").get<std::string>());

  // Every other EXR a command writes: a walkthrough's frames (each with its index) and the guide's maps.
  const fs::path frames = dir / "frames";
  r = run_cli("render " + kBox + " --model " + (dir / "run").string() + " --orbit 2 --spp 2 --width 4 --height 4 -o " +
              frames.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const std::string frame : {"0", "1"}) {
    const fs::path f = frames / ("frame_0000" + frame + ".exr");
    EXPECT_EQ(exr_attribute(f, "frame"), frame);
    EXPECT_EQ(exr_attribute(f, "steps"), "5");
    EXPECT_EQ(exr_attribute(f, "spp"), "2");
    EXPECT_EQ(exr_attribute(f, "sceneDigest"), scene.at("digest").get<std::string>());
    EXPECT_THAT(exr_attribute(f, "commandLine"), HasSubstr("--orbit 2"));
  }
  const fs::path map = dir / "guide.exr";
  r = run_cli("guide " + kBox + " --model " + (dir / "run").string() + " --pixel 64,64 --resolution 8 -o " +
              (dir / "guide.png").string() + " --exr " + map.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(exr_attribute(map, "pixel"), "64,64");
  EXPECT_EQ(exr_attribute(map, "steps"), "5");
  EXPECT_EQ(exr_attribute(map, "sceneDigest"), scene.at("digest").get<std::string>());
  EXPECT_EQ(exr_attribute(map, "spp"), "") << "a guide map takes no camera samples";
}

}  // namespace
}  // namespace clr::test
