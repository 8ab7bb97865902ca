// Malformed and hostile inputs, one table row each: every one ends with its expected exit code (2 bad input,
// 1 runtime failure, 0 for the few that are odd but valid) and one line on stderr holding the expected fragment —
// never a crash, a hang or an allocation the input alone decides. Small text cases live in tests/corpus/files;
// binary and large ones are generated here at start-up. Each command runs under a time limit and a cap on its
// address space, so a hang or an unbounded allocation fails its row instead of the machine.
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "cl/device.hpp"
#include "image/image.hpp"
#include "nn/checkpoint.hpp"
#include "nn/network.hpp"
#include "scene/fingerprint.hpp"
#include "scene/scene.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kCorpus = fs::path(CLR_SOURCE_DIR) / "tests" / "corpus" / "files";
const fs::path kBox = fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml";

// Far above what any row needs (the bundled Cornell box trains in less), far below what a hostile header asks.
constexpr int kSeconds = 120;
constexpr long kAddressSpaceKiB = 4L << 20;  // 4 GiB

struct Result {
  int exit_code;
  std::string err;
};

// Runs clradiosity with shell-word `args` under the limits above, with the environment's `env` (NAME=value words).
Result run_limited(const std::string& args, const fs::path& dir, const std::string& env = "") {
  const fs::path err = dir / ("stderr_" + std::to_string(::getpid()) + ".txt");
  const std::string cmd = "ulimit -v " + std::to_string(kAddressSpaceKiB) + "; exec env " + env + " timeout " +
                          std::to_string(kSeconds) + " '" + CLR_CLI_PATH + "' " + args + " >/dev/null 2>'" +
                          err.string() + "' </dev/null";
  const int status = std::system(cmd.c_str());
  std::ifstream in(err);
  std::ostringstream text;
  text << in.rdbuf();
  fs::remove(err);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), text.str()};
}

void write(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <typename T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

std::string random_bytes(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (auto& c : s) c = char(rng());
  return s;
}

std::string zlib(const std::string& raw) {
  uLongf size = compressBound(uLong(raw.size()));
  std::string out(size, '\0');
  compress(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()));
  out.resize(size);
  return out;
}

// A scene with a sensor and a light around one shape or texture, so that only the part under test can be wrong.
std::string scene_around(const std::string& body) {
  return "<scene version=\"3.0.0\">\n  <sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n  " +
         body + "\n</scene>\n";
}
std::string mesh_scene(const std::string& type, const fs::path& mesh) {
  return scene_around("<shape type=\"" + type + "\"><string name=\"filename\" value=\"" + mesh.string() +
                      "\"/><emitter type=\"area\"/></shape>");
}
std::string texture_scene(const fs::path& image) {
  return scene_around(
      "<shape type=\"rectangle\"><emitter type=\"area\"/><bsdf type=\"diffuse\"><texture name=\"reflectance\" "
      "type=\"bitmap\"><string name=\"filename\" value=\"" +
      image.string() + "\"/></texture></bsdf></shape>");
}
std::string envmap_scene(const fs::path& image) {
  return scene_around("<shape type=\"rectangle\"/><emitter type=\"envmap\"><string name=\"filename\" value=\"" +
                      image.string() + "\"/></emitter>");
}

std::string png_chunk(const std::string& type, const std::string& data) {
  std::string c;
  const auto be32 = [&](std::uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) c.push_back(char(v >> s));
  };
  be32(std::uint32_t(data.size()));
  c += type + data;
  const std::string crc_input = type + data;
  be32(std::uint32_t(crc32(0, reinterpret_cast<const Bytef*>(crc_input.data()), uInt(crc_input.size()))));
  return c;
}

// A PNG whose header announces width × height pixels, followed by no image data.
std::string png_header_only(std::uint32_t width, std::uint32_t height) {
  std::string ihdr;
  for (std::uint32_t v : {width, height})
    for (int s = 24; s >= 0; s -= 8) ihdr.push_back(char(v >> s));
  ihdr += std::string("\x08\x02\x00\x00\x00", 5);  // 8-bit RGB, deflate, no filter, no interlace
  return std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", ihdr) + png_chunk("IEND", "");
}

// Mitsuba's .serialized: header, zlib stream of one shape, offset table, shape count.
std::string serialized(const std::string& shape_stream, std::uint32_t count) {
  std::string f;
  put<std::uint16_t>(f, 0x041C);
  put<std::uint16_t>(f, 4);
  f += shape_stream;
  put<std::uint64_t>(f, 0);
  put<std::uint32_t>(f, count);
  return f;
}
std::string serialized_shape(std::uint64_t vertices, std::uint64_t triangles) {
  std::string raw;
  put<std::uint32_t>(raw, 0);  // flags: float positions only
  raw.push_back('\0');         // name
  put(raw, vertices);
  put(raw, triangles);
  raw += std::string(64, '\0');  // far fewer bytes than the counts need
  return zlib(raw);
}

// Mitsuba's .vol grid: "VOL", version 3, then int32 encoding, resolution and channels, a bounding box, the values.
std::string vol(std::int32_t encoding, std::int32_t xres, std::int32_t channels, const std::vector<float>& values) {
  std::string f = "VOL\x03";
  for (const std::int32_t v : {encoding, xres, 2, 2, channels}) put(f, v);
  for (int i = 0; i < 6; ++i) put(f, 0.0f);
  for (const float v : values) put(f, v);
  return f;
}

struct Case {
  std::string name;
  std::string args;  // {c} the corpus folder, {t} this run's generated files, {box} the bundled Cornell box
  int exit_code;
  std::string fragment;
};
// What gtest prints for a row (instead of its bytes).
void PrintTo(const Case& c, std::ostream* os) { *os << c.name << ": clradiosity " << c.args; }

std::string reference(const std::string& scene) {
  return "reference '" + scene + "' --spp 1 --width 4 --height 4 -o '{t}/out.exr'";
}
Case scene_case(const std::string& file, const std::string& fragment, int code = 2) {
  return {file, reference("{c}/" + file), code, fragment};
}
// A scene generated in {t} (see generate()).
Case generated_case(const std::string& file, const std::string& fragment, int code = 2) {
  return {file, reference("{t}/" + file), code, fragment};
}
Case train_case(const std::string& name, const std::string& flags, const std::string& fragment) {
  return {name, "train '{box}' " + flags + " -o '{t}/run'", 2, fragment};
}

const std::vector<Case>& cases() {
  static const std::vector<Case> all = {
      // XML
      scene_case("truncated.xml", "malformed XML"),
      scene_case("empty.xml", "malformed XML"),
      generated_case("garbage.xml", "malformed XML"),
      generated_case("garbage_after_root.xml", "malformed XML"),
      generated_case("deep.xml", "nested deeper than"),
      scene_case("unknown_shape.xml", "unsupported shape type 'teapot'"),
      scene_case("unknown_bsdf.xml", "unsupported BSDF type 'velvet'"),
      scene_case("unknown_element.xml", "<volume type=\"grid\">: 3D grids (constvolume, gridvolume) are not supported"),
      scene_case("wrong_type_tag.xml", "wrong type"),
      scene_case("wrong_type_value.xml", "malformed number 'forty'"),
      scene_case("boolean_value.xml", "expected true or false"),
      scene_case("include_cycle_a.xml", "recursive include"),
      scene_case("include_self.xml", "recursive include"),
      generated_case("include_doubling_0.xml", "files loaded through <include>"),
      scene_case("dangling_ref.xml", "unknown id 'nowhere'"),
      // Every recursion bounded: forward references, include chains, BSDFs nested through references.
      generated_case("forward_refs.xml", "plugins nested deeper than 128 levels"),
      generated_case("include_chain_0.xml", "plugins nested deeper than 128 levels"),
      generated_case("mask_chain.xml", "BSDFs nested 33 deep"),
      generated_case("blend_doubling.xml", "BSDFs in all"),
      // Memory budgeted before it is spent: 300 instances of a group holding a sphere are 79 million triangles.
      generated_case("instance_bomb.xml", "<shape type=\"instance\">: the scene reaches"),
      scene_case("laughs.xml", "after $parameter substitution"),
      scene_case("no_emitter.xml", "no emitter"),
      scene_case("zero_emitter.xml", "no emitter"),
      scene_case("no_sensor.xml", "no <sensor>"),
      scene_case("film_zero.xml", "not positive"),
      scene_case("film_negative.xml", "not positive"),
      scene_case("film_huge.xml", "exceeds the limit"),
      scene_case("film_int_overflow.xml", "integer out of range"),
      scene_case("nan_matrix.xml", "malformed number 'nan'"),
      scene_case("inf_scale.xml", "not finite"),
      scene_case("overflow_number.xml", "malformed number '1e39'"),
      scene_case("zero_scale.xml", "singular"),
      scene_case("degenerate_lookat.xml", "degenerate lookat"),
      scene_case("fov_180.xml", "fov must lie in (0, 180)"),
      scene_case("negative_radiance.xml", "radiance must be non-negative"),
      scene_case("negative_environment.xml", "<emitter type=\"constant\">: radiance must be non-negative"),
      // Light never negative, wherever it comes from: texels (not only their mean), scales, reflectances.
      generated_case("negative_texel_radiance.xml", "radiance must be non-negative and finite (a texel holds -4)"),
      generated_case("negative_texel_reflectance.xml",
                     "reflectance must be non-negative and finite (a texel holds -4)"),
      generated_case("negative_texel_spot.xml", "texture must be non-negative and finite (a texel holds -4)"),
      generated_case("negative_texel_projector.xml", "irradiance must be non-negative and finite (a texel holds -4)"),
      generated_case("negative_scale_projector.xml", "<emitter type=\"projector\">: scale must be non-negative"),
      generated_case("negative_scale_envmap.xml", "<emitter type=\"envmap\">: scale must be non-negative"),
      generated_case("negative_pixel_envmap.xml", "environment map has a negative pixel at (3, 1)"),
      generated_case("negative_checker.xml", "reflectance must be non-negative and finite (a texel holds -0.2)"),
      generated_case("negative_blend_weight.xml", "weight must be non-negative and finite (it is -0.5)"),
      scene_case("missing_mesh.xml", "not found"),
      scene_case("bad_spectrum.xml", "<spectrum name=\"radiance\">: wavelengths must increase"),
      scene_case("bad_hex_colour.xml", "malformed colour '#12345g'"),
      scene_case("spot_beam_wider.xml", "<emitter type=\"spot\">: beam_width must lie in [0, cutoff_angle]"),
      scene_case("thinlens_no_aperture.xml", "missing property 'aperture_radius'"),
      scene_case("shapegroup_emitter.xml", "cannot emit"),
      scene_case("participating_medium.xml", "<medium name=\"interior\" type=\"homogeneous\">: participating media"),
      scene_case("polarized_integrator.xml", "<integrator type=\"stokes\">: polarization is not modelled"),
      generated_case("device_mesh.xml", "'/dev/zero' is not a regular file"),
      generated_case("device_include.xml", "'/dev/zero' is not a regular file"),
      {"device_scene", reference("/dev/zero"), 2, "scene file /dev/zero is not a regular file"},
      // OBJ
      generated_case("index_out_of_range.obj.xml", "vertex index is out of range"),
      generated_case("negative_index.obj.xml", "vertex index is out of range"),
      generated_case("nan_vertex.obj.xml", "'nan' is not a finite number"),
      generated_case("inf_vertex.obj.xml", "not finite"),
      generated_case("degenerate.obj.xml", "no emitter"),
      // Degenerate meshes occur in real scenes (the shared staircase has one): never hit, never sampled, accepted.
      generated_case("degenerate_beside_light.xml", "", 0),
      {"train_degenerate_only", "train '{t}/degenerate_under_sky.xml' --steps 1 -o '{t}/run'", 2,
       "no surface with a non-delta BSDF to sample"},
      generated_case("truncated.obj.xml", "no triangles"),
      generated_case("no_faces.obj.xml", "no triangles"),
      generated_case("garbage.obj.xml", "obj"),
      // PLY
      generated_case("billions.ply.xml", "announces 4000000000 'vertex' elements"),
      generated_case("negative_count.ply.xml", "'vertex' elements, more than"),
      generated_case("no_end_header.ply.xml", "no end_header"),
      generated_case("ply_index.ply.xml", "index out of range"),
      generated_case("ply_truncated.ply.xml", "more than the file's 12 bytes"),
      generated_case("ply_short_list.ply.xml", "ends early"),
      generated_case("ply_bad_type.ply.xml", "property type 'quaternion' unknown"),
      generated_case("ply_empty_elements.ply.xml", "", 0),
      generated_case("billions_binary.ply.xml", "announces 1000000000000 'face' elements"),
      generated_case("truncated_binary.ply.xml", "more than the file's 20 bytes"),
      generated_case("huge_list.ply.xml", "list length out of range"),
      generated_case("nan_binary.ply.xml", "not finite"),
      // Indices and duplicates checked by every mesh reader before normals are computed from them.
      generated_case("ply_index_smooth.xml", "index out of range"),
      generated_case("ply_index_crease.xml", "index out of range"),
      generated_case("ply_two_vertex_elements.ply.xml", "PLY element 'vertex' is declared twice"),
      generated_case("ply_two_x.ply.xml", "PLY property 'x' of element 'vertex' is declared twice"),
      generated_case("ply_fraction_index.ply.xml", "PLY face index 1.500000 is not a whole number"),
      // Parsing is linear: creased normals of a fan of 500 000 coplanar triangles about one vertex (each corner at
      // the centre compared with every other was 2.5e11 comparisons).
      generated_case("fan_crease.xml", "", 0),
      generated_case("index.serialized.xml", "triangle vertex index 7 is out of range"),
      // A valid triangle followed by 3 GiB of zeros in its zlib stream (3 MB on disk): read as the triangle it is,
      // never inflated whole (beyond the 4 GiB address-space limit of these rows).
      generated_case("bomb.serialized.xml", "", 0),
      // Mesh attributes (mesh_attribute textures)
      generated_case("attribute_missing.xml",
                     "mesh_attribute texture 'tex' reads attribute 'face_color', which shape 'attributed' does not "
                     "have (it has vertex_color, face_weight)"),
      generated_case("attribute_rgba.xml", "which has 4 channels: only 1 or 3 can be evaluated"),
      generated_case("attribute_nan.xml", "which holds a non-finite value"),
      generated_case("attribute_bad_name.xml", "a mesh attribute's name starts with 'vertex_' or 'face_', not 'color'"),
      generated_case("attribute_on_light.xml", "only shapes have mesh attributes"),
      // .serialized
      generated_case("garbage.serialized.xml", "not a serialized mesh"),
      generated_case("shape_table.serialized.xml", "more than its size can index"),
      generated_case("bad_zlib.serialized.xml", "corrupt compressed data"),
      generated_case("counts.serialized.xml", "bytes of compressed data can hold"),
      // .vol (sdfgrid)
      generated_case("garbage.vol.xml", "no 'VOL' magic"),
      generated_case("encoding.vol.xml", "unsupported .vol encoding 2"),
      generated_case("zero_resolution.vol.xml", "resolution 0 along x"),
      generated_case("huge_resolution.vol.xml", "resolution 2000000000 along x"),
      generated_case("truncated.vol.xml", "more than the file's 28 bytes of data hold"),
      generated_case("channels.vol.xml", "3 channels, but an SDF grid has 1"),
      generated_case("nan.vol.xml", "value 3 is not finite"),
      generated_case("no_surface.vol.xml", "no zero crossing"),
      // textures and environment maps
      generated_case("garbage.png.xml", "cannot read image"),
      generated_case("huge.png.xml", "exceeds the limit"),
      generated_case("truncated.exr.xml", "cannot read EXR"),
      generated_case("garbage.exr.xml", "cannot read EXR"),
      generated_case("huge_window.exr.xml", "EXR"),
      generated_case("nan_envmap.exr.xml", "non-finite pixels"),
      generated_case("nan_texture.exr.xml", "non-finite texels"),
      // Image dimensions against the bytes present, in every image reader; truncated pixels refused.
      generated_case("huge.hdr.xml", "16384x8192 pixels, more than its"),
      generated_case("huge_envmap.hdr.xml", "16384x8192 pixels, more than its"),
      generated_case("truncated.hdr.xml", "is truncated"),
      generated_case("truncated_envmap.hdr.xml", "is truncated"),
      generated_case("header_only.png.xml", "bytes can hold"),
      generated_case("truncated.png.xml", "image"),
      generated_case("truncated.ppm.xml", "bytes can hold"),
      generated_case("big_window.exr.xml", "bytes can hold"),
      // command-line options
      train_case("train_learning_rate_nan", "--steps 1 --learning-rate nan", "--learning-rate"),
      train_case("train_learning_rate_negative", "--steps 1 --learning-rate -1", "--learning-rate"),
      train_case("train_batch_zero", "--steps 1 --batch 0", "--batch"),
      train_case("train_samples_zero", "--steps 1 --samples 0", "--samples"),
      train_case("train_steps_negative", "--steps -1", "--steps"),
      train_case("train_minutes_nan", "--minutes nan", "--minutes"),
      train_case("train_minutes_inf", "--minutes inf", "--minutes"),
      train_case("train_seed_negative", "--steps 1 --seed -1", "--seed"),
      train_case("train_steps_huge", "--steps 99999999999999999999999", "--steps"),
      {"train_run_dir_is_a_device", "train '{box}' --steps 1 -o /dev/null", 2, "exists and is not a directory"},
      {"render_spp_zero", "render '{box}' --model '{t}/none' --spp 0 -o '{t}/out.exr'", 2, "--spp"},
      {"render_width_negative", "render '{box}' --model '{t}/none' --width -4 -o '{t}/out.exr'", 2, "--width"},
      {"render_camera_nan", "render '{box}' --model '{t}/none' --camera 0,0,nan,0,0,1,0,1,0,40 -o '{t}/out.exr'", 2,
       "--camera"},
      {"render_spp_huge", "render '{box}' --model '{t}/none' --spp 1e30 -o '{t}/out.exr'", 2, "--spp"},
      {"reference_spp_zero", "reference '{box}' --spp 0 -o '{t}/out.exr'", 2, "--spp"},
      {"reference_max_depth", "reference '{box}' --spp 1 --max-depth -2 -o '{t}/out.exr'", 2, "--max-depth"},
      {"reference_pixels", "reference '{box}' --spp 1 --width 65536 --height 65536 -o '{t}/out.exr'", 2,
       "--width × --height"},
      {"residual_points_zero", "residual '{box}' --model '{t}/none' --points 0", 2, "--points"},
      {"residual_samples_nan", "residual '{box}' --model '{t}/none' --samples nan", 2, "--samples"},
      {"reference_output_directory", "reference '{box}' --spp 1 --width 4 --height 4 -o '{t}/dir.exr'", 2,
       "is a directory"},
      {"render_png_directory", "render '{box}' --model '{t}/none' -o '{t}/out.exr' --png '{t}/dir.png'", 2,
       "is a directory"},
      {"compare_error_map_directory", "compare '{t}/good.exr' '{t}/good.exr' --error-map '{t}/dir.png'", 2,
       "is a directory"},
      // config.json
      train_case("config_malformed", "--steps 1 --config '{c}/config_malformed.json'", "malformed JSON"),
      train_case("config_unknown_key", "--steps 1 --config '{c}/config_unknown_key.json'", "'smaples'"),
      train_case("config_wrong_type", "--steps 1 --config '{c}/config_wrong_type.json'", "'samples'"),
      train_case("config_learning_rate", "--steps 1 --config '{c}/config_learning_rate.json'", "'adam.learning_rate'"),
      train_case("config_incident_samples", "--steps 1 --config '{c}/config_incident_samples.json'", "batch × samples"),
      // JSON inputs: one nesting limit for all, every key known at every depth, integers never narrowed, a value
      // echoed clipped, and no read that blocks (a FIFO).
      train_case("config_deep", "--steps 1 --config '{t}/deep.json'", "nested deeper than 64"),
      train_case("config_huge_value", "--steps 1 --config '{t}/huge_value.json'", "method must be isnr or nr"),
      train_case("config_fifo", "--steps 1 --config '{t}/fifo'", "is not a regular file"),
      train_case("config_nested_unknown", "--steps 1 --config '{t}/nested_unknown.json'", "unknown key 'widht'"),
      train_case("config_guide_unknown", "--steps 1 --config '{t}/guide_unknown.json'",
                 "unknown key 'encoder.grid.levles'"),
      train_case("config_batch_wraps", "--steps 1 --config '{t}/batch_wraps.json'",
                 "'batch' 4294967808 is out of range"),
      train_case("config_seed_negative", "--steps 1 --config '{t}/seed_negative.json'", "'seed' -1 is out of range"),
      {"scene_fifo", "reference '{t}/fifo' --spp 1 -o '{t}/out.exr'", 2, "not a regular file"},
      {"compare_fifo", "compare '{t}/fifo' '{t}/fifo'", 2, "not a regular file"},
      {"checkpoint_fifo", "render '{box}' --model '{t}/fifo_run' -o '{t}/out.exr'", 2, "not a regular file"},
      {"run_config_fifo", "train '{box}' --resume --steps 1 -o '{t}/fifo_config_run'", 2, "not a regular file"},
      {"run_config_malformed", "train '{box}' --resume --steps 1 -o '{t}/malformed_config_run'", 2,
       "malformed JSON in run config"},
      {"run_log_nan", "train '{box}' --resume --steps 1 -o '{t}/nan_log_run'", 2, "log.csv:2: the seconds column"},
      // A report reads the same run files, and names the one at fault before anything is rendered.
      {"report_no_run", "report '{t}/no_such_run' -o '{t}/r.html'", 2, "no_such_run: no such run folder"},
      {"report_config_fifo", "report '{t}/fifo_config_run' -o '{t}/r.html'", 2, "not a regular file"},
      {"report_config_malformed", "report '{t}/malformed_config_run' -o '{t}/r.html'", 2,
       "malformed JSON in run config"},
      {"report_log_fields", "report '{t}/nan_log_run' -o '{t}/r.html'", 2,
       "log.csv:2: 3 fields where the header names 2"},
      {"report_not_html", "report '{t}/nan_log_run' -o '{t}/r.png'", 2, "the report must end in .html"},
      // An output is never one of the command's inputs, nor another output: by identity, links followed. (An input
      // named as an image output without an image's extension is refused for the extension, first.)
      {"output_is_scene", "reference '{t}/box_copy.xml' --spp 1 -o '{t}/box_copy.xml'", 2,
       "the extension names the image format"},
      {"output_links_to_scene", "reference '{t}/box_copy.xml' --spp 1 -o '{t}/box_link.exr'", 2, "is the input"},
      {"output_is_checkpoint", "render '{box}' --model '{t}/hostile_run' -o '{t}/hostile_run/model.clr'", 2,
       "the extension names the image format"},
      {"png_is_output", "render '{box}' --model '{t}/hostile_run' -o '{t}/same.png' --png '{t}/same.png'", 2,
       "is also the output of -o"},
      {"sweep_output_is_scene", "sweep '{t}/sweep_holds_scene/tables.md' --minutes 1 -o '{t}/sweep_holds_scene'", 2,
       "tables.md in -o: output"},
      {"error_map_is_reference", "compare '{t}/nan.exr' '{t}/nan.exr' --error-map '{t}/nan.exr'", 2,
       "the extension names the image format"},
      // Coordinates a single-precision ray tracer cannot take are refused before Embree sees them.
      {"camera_far", "render '{box}' --model '{t}/hostile_run' --camera 1e20,0,0,0,0,0,0,1,0,40 -o '{t}/out.exr'", 2,
       "--camera: the camera's position lies beyond"},
      {"sensor_far", "reference '{t}/far_sensor.xml' --spp 1 -o '{t}/out.exr'", 2, "the camera's position lies beyond"},
      {"vertex_far", "reference '{t}/far_vertex.xml' --spp 1 -o '{t}/out.exr'", 2, "lies beyond ±1e12"},
      // checkpoints
      {"checkpoint_device", "render '{box}' --model /dev/zero -o '{t}/out.exr'", 2, "not a regular file"},
      {"checkpoint_garbage", "render '{box}' --model '{t}/garbage_run' -o '{t}/out.exr'", 2, "bad magic"},
      {"checkpoint_truncated", "render '{box}' --model '{t}/truncated_run' -o '{t}/out.exr'", 2, "truncated"},
      {"checkpoint_hostile_config", "render '{box}' --model '{t}/hostile_run' -o '{t}/out.exr'", 2,
       "tensor 'mlp.params'"},
      {"checkpoint_config_not_json", "render '{box}' --model '{t}/not_json_run' -o '{t}/out.exr'", 2,
       "malformed JSON in the network config of checkpoint"},
      // One terminal-safe line: control characters escaped, invalid UTF-8 shown as bytes, never printed raw.
      generated_case("newline_type.xml", "unsupported shape type 'te\\napot'"),
      generated_case("escape_type.xml", "unsupported shape type '\\x1b[31mred'"),
      {"option_bytes", "reference '{box}' --spp '1\xff' -o '{t}/out.exr'", 2, "\\xff"},
      {"scene_name_not_utf8", "train '{t}/box\xff.xml' --steps 1 -o '{t}/run'", 2, "is not valid UTF-8"},
      // Refused before the work: names the file system cannot hold, an output FIFO that nobody reads.
      {"output_name_too_long", "reference '{box}' --spp 1 -o '{t}/" + std::string(300, 'n') + ".exr'", 2,
       "a file name may have"},
      {"error_map_name_too_long",
       "compare '{t}/good.exr' '{t}/good.exr' --error-map '{t}/" + std::string(300, 'm') + ".png'", 2,
       "a file name may have"},
      {"render_png_name_too_long",
       "render '{box}' --model '{t}/none' -o '{t}/out.exr' --png '{t}/" + std::string(256, 'p') + ".png'", 2,
       "a file name may have"},
      // images compared
      {"compare_garbage", "compare '{t}/garbage.exr' '{t}/garbage.exr'", 2, "cannot read EXR"},
      {"compare_huge_window", "compare '{t}/huge_window.exr' '{t}/huge_window.exr'", 2, "EXR"},
  };
  return all;
}

// Writes every generated input into `t`.
void generate(const fs::path& t) {
  write(t / "garbage.xml", random_bytes(4096, 1));
  write(t / "garbage_after_root.xml", "<scene version=\"3.0.0\">" + random_bytes(4096, 2));
  {
    constexpr int kDepth = 100000;
    std::string deep = "<scene version=\"3.0.0\"><shape type=\"rectangle\">";
    for (int i = 0; i < kDepth; ++i) deep += "<bsdf type=\"twosided\">";
    for (int i = 0; i < kDepth; ++i) deep += "</bsdf>";
    write(t / "deep.xml", deep + "</shape></scene>");
  }
  // Text meshes of the corpus, each wrapped in a scene.
  for (const auto& e : fs::directory_iterator(kCorpus)) {
    const std::string ext = e.path().extension().string();
    if (ext == ".obj" || ext == ".ply")
      write(t / (e.path().filename().string() + ".xml"), mesh_scene(ext.substr(1), e.path()));
  }
  // Files a scene names that would be read forever.
  write(t / "device_mesh.xml", mesh_scene("obj", "/dev/zero"));
  write(t / "device_include.xml", "<scene version=\"3.0.0\"><include filename=\"/dev/zero\"/></scene>");
  // Each file includes the next twice: 2^40 loads, without any recursion.
  constexpr int kDoublings = 40;
  for (int i = 0; i < kDoublings; ++i) {
    const std::string next = "include_doubling_" + std::to_string(i + 1) + ".xml";
    write(t / ("include_doubling_" + std::to_string(i) + ".xml"),
          "<scene version=\"3.0.0\">\n" +
              (i + 1 < kDoublings ? "<include filename=\"" + next + "\"/><include filename=\"" + next + "\"/>\n"
                                  : std::string()) +
              "</scene>\n");
  }
  {
    // 10 000 BSDFs each referring to the next, declared further down: built recursively from the first.
    constexpr int kChain = 10000;
    std::string chain = "<bsdf type=\"diffuse\" id=\"b" + std::to_string(kChain) + "\"/>";
    for (int i = kChain - 1; i >= 0; --i)
      chain = "<bsdf type=\"mask\" id=\"b" + std::to_string(i) + "\"><ref id=\"b" + std::to_string(i + 1) +
              "\"/></bsdf>\n" + chain;
    write(t / "forward_refs.xml",
          scene_around("<shape type=\"rectangle\"><emitter type=\"area\"/><ref id=\"b0\"/></shape>\n" + chain));
    // 33 masks each nesting the one before (no forward reference: each is built when declared).
    std::string masks = "<bsdf type=\"diffuse\" id=\"m0\"/>\n";
    for (int i = 1; i <= 33; ++i)
      masks +=
          "<bsdf type=\"mask\" id=\"m" + std::to_string(i) + "\"><ref id=\"m" + std::to_string(i - 1) + "\"/></bsdf>\n";
    write(t / "mask_chain.xml", scene_around(masks + "<shape type=\"rectangle\"><emitter type=\"area\"/>"
                                                     "<ref id=\"m33\"/></shape>"));
    // 20 blends each nesting the one before twice: 2^20 evaluations per sample at the top.
    std::string blends = "<bsdf type=\"diffuse\" id=\"d0\"/>\n";
    for (int i = 1; i <= 20; ++i)
      blends += "<bsdf type=\"blendbsdf\" id=\"d" + std::to_string(i) + "\"><ref id=\"d" + std::to_string(i - 1) +
                "\"/><ref id=\"d" + std::to_string(i - 1) + "\"/></bsdf>\n";
    write(t / "blend_doubling.xml", scene_around(blends + "<shape type=\"rectangle\"><emitter type=\"area\"/>"
                                                          "<ref id=\"d20\"/></shape>"));
    // A sphere stretched into an ellipsoid is tessellated (262 144 triangles); an exact one would cost nothing.
    std::string instances =
        "<shape type=\"rectangle\"><emitter type=\"area\"/></shape>\n<shape type=\"shapegroup\" id=\"g\">"
        "<shape type=\"sphere\"><transform name=\"to_world\"><scale z=\"2\"/></transform></shape></shape>\n";
    for (int i = 0; i < 300; ++i) instances += "<shape type=\"instance\"><ref id=\"g\"/></shape>\n";
    write(t / "instance_bomb.xml", scene_around(instances));
    // 200 files each including the next (under the limit on files loaded, beyond the nesting limit).
    for (int i = 0; i < 200; ++i)
      write(t / ("include_chain_" + std::to_string(i) + ".xml"),
            "<scene version=\"3.0.0\">" +
                (i + 1 < 200 ? "<include filename=\"include_chain_" + std::to_string(i + 1) + ".xml\"/>"
                             : std::string()) +
                "</scene>\n");
  }
  const std::string degenerate =
      "<shape type=\"obj\"><string name=\"filename\" value=\"" + (kCorpus / "degenerate.obj").string() + "\"/>";
  write(t / "degenerate_beside_light.xml",
        scene_around(degenerate + "</shape><shape type=\"rectangle\"><emitter type=\"area\"/></shape>"));
  write(t / "degenerate_under_sky.xml", scene_around(degenerate + "</shape><emitter type=\"constant\"/>"));
  write(t / "garbage.obj", random_bytes(4096, 3));
  write(t / "garbage.obj.xml", mesh_scene("obj", t / "garbage.obj"));

  // Binary PLY.
  const std::string vertex_header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\n";
  const std::string face_list = "property list uchar int vertex_indices\nend_header\n";
  const float triangle[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::string vertices(reinterpret_cast<const char*>(triangle), sizeof triangle);
  std::string face;
  face.push_back(char(3));
  for (std::int32_t i : {0, 1, 2}) put(face, i);
  write(t / "billions_binary.ply", vertex_header + "element face 1000000000000\n" + face_list + vertices + face);
  write(t / "truncated_binary.ply", vertex_header + "element face 1\n" + face_list + vertices.substr(0, 20));
  {
    std::string list = vertex_header + "element face 1\nproperty list uint int vertex_indices\nend_header\n" + vertices;
    put<std::uint32_t>(list, 4000000000u);
    write(t / "huge_list.ply", list + std::string(64, '\0'));
  }
  {
    float nan_triangle[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    nan_triangle[4] = std::numeric_limits<float>::quiet_NaN();
    write(t / "nan_binary.ply", vertex_header + "element face 1\n" + face_list +
                                    std::string(reinterpret_cast<const char*>(nan_triangle), sizeof nan_triangle) +
                                    face);
  }
  for (const char* f : {"billions_binary.ply", "truncated_binary.ply", "huge_list.ply", "nan_binary.ply"})
    write(t / (std::string(f) + ".xml"), mesh_scene("ply", t / f));
  {
    constexpr std::uint32_t kFan = 500000;
    std::string fan = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(kFan + 2) +
                      "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(kFan) +
                      "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const float v : {0.0f, 0.0f, 0.0f}) put(fan, v);
    for (std::uint32_t k = 0; k <= kFan; ++k) {
      const double a = 6.283185307179586 * double(k) / double(kFan + 1);
      for (const float v : {float(std::cos(a)), float(std::sin(a)), 0.0f}) put(fan, v);
    }
    for (std::uint32_t k = 0; k < kFan; ++k) {
      fan.push_back(char(3));
      for (const std::int32_t i : {0, std::int32_t(k + 1), std::int32_t(k + 2)}) put(fan, i);
    }
    write(t / "fan.ply", fan);
    write(t / "fan_crease.xml",
          scene_around("<shape type=\"ply\"><string name=\"filename\" value=\"" + (t / "fan.ply").string() +
                       "\"/><float name=\"max_smooth_angle\" value=\"30\"/>"
                       "<emitter type=\"area\"/></shape>"));
  }
  // A face index beyond the vertices under smoothing (the normals are computed from the indices) and creasing.
  for (const auto& [name, option] : {std::pair<std::string, std::string>{"smooth", ""},
                                     {"crease", "<float name=\"max_smooth_angle\" value=\"30\"/>"}})
    write(t / ("ply_index_" + name + ".xml"),
          scene_around("<shape type=\"rectangle\"><emitter type=\"area\"/></shape><shape type=\"ply\">"
                       "<string name=\"filename\" value=\"" +
                       (kCorpus / "ply_index.ply").string() + "\"/>" + option + "</shape>"));
  {
    const std::string ascii_triangle = "0 0 0\n1 0 0\n0 1 0\n";
    write(t / "ply_two_vertex_elements.ply",
          "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
          "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
          "property list uchar int vertex_indices\nend_header\n" +
              ascii_triangle + ascii_triangle + "3 0 1 2\n");
    write(t / "ply_two_x.ply",
          "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float x\nproperty float y\n"
          "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
          "0 0 0 0\n1 1 0 0\n0 0 1 0\n3 0 1 2\n");
    write(t / "ply_fraction_index.ply",
          "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
          "element face 1\nproperty list uchar float vertex_indices\nend_header\n" +
              ascii_triangle + "3 0 1.5 2\n");
    for (const char* f : {"ply_two_vertex_elements.ply", "ply_two_x.ply", "ply_fraction_index.ply"})
      write(t / (std::string(f) + ".xml"), mesh_scene("ply", t / f));
  }

  // Mesh attributes: a triangle with vertex colours (and alpha) and a face weight (NaN in one file), under a light,
  // its reflectance the mesh_attribute texture `tex`.
  for (const bool nan : {false, true}) {
    std::string ply = vertex_header +
                      "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
                      "element face 1\nproperty list uchar int vertex_indices\nproperty float weight_0\nend_header\n";
    for (int v = 0; v < 3; ++v) {
      ply += vertices.substr(std::size_t(12 * v), 12);
      ply += std::string(4, char(200));
    }
    ply += face;
    put(ply, nan ? std::numeric_limits<float>::quiet_NaN() : 0.5f);
    write(t / (nan ? "attribute_nan.ply" : "attribute.ply"), ply);
  }
  const auto attributed = [&](const std::string& file, const std::string& name) {
    return scene_around(
        "<shape type=\"rectangle\"><emitter type=\"area\"/></shape>\n"
        "  <texture type=\"mesh_attribute\" id=\"tex\"><string name=\"name\" value=\"" +
        name + "\"/></texture>\n  <shape type=\"ply\" id=\"attributed\"><string name=\"filename\" value=\"" +
        (t / file).string() + "\"/><bsdf type=\"diffuse\"><ref name=\"reflectance\" id=\"tex\"/></bsdf></shape>");
  };
  write(t / "attribute_missing.xml", attributed("attribute.ply", "face_color"));
  write(t / "attribute_rgba.xml", attributed("attribute.ply", "vertex_color"));
  write(t / "attribute_nan.xml", attributed("attribute_nan.ply", "face_weight"));
  write(t / "attribute_bad_name.xml", attributed("attribute.ply", "color"));
  write(t / "attribute_on_light.xml",
        scene_around("<shape type=\"rectangle\"><emitter type=\"area\"/></shape>\n  <emitter type=\"spot\">"
                     "<texture type=\"mesh_attribute\" name=\"texture\"><string name=\"name\" value=\"face_weight\"/>"
                     "</texture></emitter>"));

  // .serialized
  write(t / "garbage.serialized", random_bytes(4096, 4));
  write(t / "shape_table.serialized", serialized(std::string(16, '\0'), 0xffffffffu));
  write(t / "bad_zlib.serialized", serialized(random_bytes(256, 5), 1));
  write(t / "counts.serialized", serialized(serialized_shape(1ull << 31, 1ull << 31), 1));
  {  // one triangle over three vertices whose last index lies beyond them
    std::string raw;
    put<std::uint32_t>(raw, 0);
    raw.push_back('\0');
    put<std::uint64_t>(raw, 3);
    put<std::uint64_t>(raw, 1);
    for (const float v : triangle) put(raw, v);
    for (const std::uint32_t i : {0u, 1u, 7u}) put(raw, i);
    write(t / "index.serialized", serialized(zlib(raw), 1));
    raw.resize(raw.size() - 4);
    put<std::uint32_t>(raw, 2);
    // The same triangle, valid, then 3 GiB of zeros, deflated a chunk at a time.
    z_stream z{};
    deflateInit(&z, Z_BEST_SPEED);
    std::string bomb;
    const std::string zeros(1 << 20, '\0');
    char out[1 << 16];
    const auto pump = [&](const std::string& in, int flush) {
      z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
      z.avail_in = uInt(in.size());
      do {
        z.next_out = reinterpret_cast<Bytef*>(out);
        z.avail_out = sizeof out;
        deflate(&z, flush);
        bomb.append(out, sizeof out - z.avail_out);
      } while (z.avail_out == 0);
    };
    pump(raw, Z_NO_FLUSH);
    for (int i = 0; i < 3 * 1024; ++i) pump(zeros, Z_NO_FLUSH);
    pump("", Z_FINISH);
    deflateEnd(&z);
    write(t / "bomb.serialized", serialized(bomb, 1));
  }
  for (const char* f : {"garbage.serialized", "shape_table.serialized", "bad_zlib.serialized", "counts.serialized",
                        "index.serialized", "bomb.serialized"})
    write(t / (std::string(f) + ".xml"), mesh_scene("serialized", t / f));

  // .vol (sdfgrid)
  {
    const std::vector<float> crossing = {-1, 1, -1, 1, -1, 1, -1, 1};
    std::vector<float> nan = crossing;
    nan[3] = std::numeric_limits<float>::quiet_NaN();
    write(t / "garbage.vol", random_bytes(4096, 8));
    write(t / "encoding.vol", vol(2, 2, 1, crossing));
    write(t / "zero_resolution.vol", vol(1, 0, 1, {}));
    write(t / "huge_resolution.vol", vol(1, 2000000000, 1, crossing));
    write(t / "truncated.vol", vol(1, 2, 1, std::vector<float>(7, 0.0f)));
    write(t / "channels.vol", vol(1, 2, 3, std::vector<float>(24, -1.0f)));
    write(t / "nan.vol", vol(1, 2, 1, nan));
    write(t / "no_surface.vol", vol(1, 2, 1, std::vector<float>(8, 1.0f)));
    for (const char* f : {"garbage.vol", "encoding.vol", "zero_resolution.vol", "huge_resolution.vol", "truncated.vol",
                          "channels.vol", "nan.vol", "no_surface.vol"})
      write(t / (std::string(f) + ".xml"), mesh_scene("sdfgrid", t / f));
  }

  // Images.
  write(t / "garbage.png", std::string("\x89PNG\r\n\x1a\n", 8) + random_bytes(512, 6));
  // Within stb's own limit (1 GiB decoded), beyond ours.
  write(t / "huge.png", png_header_only(20000, 10000));
  image::Image small(8, 4);
  for (auto& v : small.rgb) v = 0.5f;
  image::write_exr(t / "good.exr", small);
  const std::string exr = read(t / "good.exr");
  write(t / "truncated.exr", exr.substr(0, exr.size() / 2));
  write(t / "garbage.exr", std::string("\x76\x2f\x31\x01\x02\x00\x00\x00", 8) + random_bytes(512, 7));
  {
    // The header's dataWindow (box2i: xMin yMin xMax yMax) made to announce 2^20 × 2^20 pixels.
    std::string huge = exr;
    const std::string key = std::string("dataWindow\0box2i\0", 17);
    const auto at = huge.find(key);
    if (at != std::string::npos) {
      const std::int32_t max = 1 << 20;
      std::memcpy(&huge[at + key.size() + 4 + 8], &max, 4);
      std::memcpy(&huge[at + key.size() + 4 + 12], &max, 4);
    }
    write(t / "huge_window.exr", huge);
  }
  {
    const std::string rgbe = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";
    write(t / "huge.hdr", rgbe + "-Y 8192 +X 16384\n" + random_bytes(64, 9));
    // 16 × 4 flat pixels need 256 bytes; 100 are there.
    write(t / "truncated.hdr", rgbe + "-Y 4 +X 16\n" + std::string(100, char(0x80)));
    write(t / "header_only.png", png_header_only(8000, 8000));
    write(t / "truncated.ppm", "P6\n64 64\n255\n" + random_bytes(100, 10));
    image::Image noise(64, 64);
    std::mt19937 rng(11);
    for (auto& v : noise.rgb) v = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
    image::write_png(t / "whole.png", noise);
    const std::string png = read(t / "whole.png");
    write(t / "truncated.png", png.substr(0, png.size() / 2));
    // The header's dataWindow made to announce 4096 × 4096 pixels (within the pixel limit) over a few hundred bytes.
    std::string big = exr;
    const std::string key = std::string("dataWindow\0box2i\0", 17);
    const auto at = big.find(key);
    if (at != std::string::npos) {
      const std::int32_t max = 4095;
      std::memcpy(&big[at + key.size() + 4 + 8], &max, 4);
      std::memcpy(&big[at + key.size() + 4 + 12], &max, 4);
    }
    // Padded past the line offset table OpenEXR reads first (256 chunks of 16 lines): the pixels are what is missing.
    write(t / "big_window.exr", big + std::string(256 * 8 + 64, '\0'));
    for (const char* f :
         {"huge.hdr", "truncated.hdr", "header_only.png", "truncated.ppm", "truncated.png", "big_window.exr"})
      write(t / (std::string(f) + ".xml"), texture_scene(t / f));
    write(t / "huge_envmap.hdr.xml", envmap_scene(t / "huge.hdr"));
    write(t / "truncated_envmap.hdr.xml", envmap_scene(t / "truncated.hdr"));
  }
  {
    // One texel of -4 among positive ones, the mean positive.
    image::Image negative(8, 4);
    for (auto& v : negative.rgb) v = 1.0f;
    negative.pixel(3, 1)[0] = -4.0f;
    image::write_exr(t / "negative.exr", negative);
    const std::string bitmap = "<texture type=\"bitmap\" name=\"NAME\"><string name=\"filename\" value=\"" +
                               (t / "negative.exr").string() + "\"/></texture>";
    const auto named = [&](const std::string& name) {
      std::string b = bitmap;
      return b.replace(b.find("NAME"), 4, name);
    };
    const std::string light = "<shape type=\"rectangle\"><emitter type=\"area\"/></shape>";
    write(t / "negative_texel_radiance.xml",
          scene_around("<shape type=\"rectangle\"><emitter type=\"area\">" + named("radiance") + "</emitter></shape>"));
    write(t / "negative_texel_reflectance.xml",
          scene_around(light + "<shape type=\"rectangle\"><bsdf type=\"diffuse\">" + named("reflectance") +
                       "</bsdf></shape>"));
    write(t / "negative_texel_spot.xml",
          scene_around(light + "<emitter type=\"spot\">" + named("texture") + "</emitter>"));
    write(t / "negative_texel_projector.xml",
          scene_around(light + "<emitter type=\"projector\">" + named("irradiance") + "</emitter>"));
    write(t / "negative_scale_projector.xml",
          scene_around(light + "<emitter type=\"projector\"><rgb name=\"irradiance\" value=\"1\"/>"
                               "<float name=\"scale\" value=\"-2\"/></emitter>"));
    write(t / "negative_scale_envmap.xml",
          scene_around("<shape type=\"rectangle\"/><emitter type=\"envmap\"><string name=\"filename\" value=\"" +
                       (t / "good.exr").string() + "\"/><float name=\"scale\" value=\"-1\"/></emitter>"));
    write(t / "negative_pixel_envmap.xml", envmap_scene(t / "negative.exr"));
    write(t / "negative_checker.xml",
          scene_around(light + "<shape type=\"rectangle\"><bsdf type=\"diffuse\"><texture type=\"checkerboard\" "
                               "name=\"reflectance\"><rgb name=\"color0\" value=\"-0.2\"/><rgb name=\"color1\" "
                               "value=\"1\"/></texture></bsdf></shape>"));
    write(t / "negative_blend_weight.xml",
          scene_around(light + "<shape type=\"rectangle\"><bsdf type=\"blendbsdf\"><float name=\"weight\" "
                               "value=\"-0.5\"/><bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/></bsdf></shape>"));
  }
  small.rgb[5] = std::numeric_limits<float>::quiet_NaN();
  image::write_exr(t / "nan.exr", small);
  for (const char* f : {"garbage.png", "huge.png", "truncated.exr", "garbage.exr", "huge_window.exr"})
    write(t / (std::string(f) + ".xml"), texture_scene(t / f));
  write(t / "nan_texture.exr.xml", texture_scene(t / "nan.exr"));
  write(t / "nan_envmap.exr.xml", envmap_scene(t / "nan.exr"));

  // Checkpoints (render --model RUN_DIR), each beside the box's scene record: a model without one is refused before
  // its checkpoint is read.
  nlohmann::json box_record;
  {
    const auto f = scene::fingerprint(scene::load_scene(kBox));
    nlohmann::json files = nlohmann::json::array();
    for (const auto& e : f.files) files.push_back({{"name", e.name}, {"digest", e.digest}});
    box_record = {{"scene", f.scene.string()}, {"digest", f.digest}, {"files", files}};
  }
  for (const char* run : {"garbage_run", "truncated_run", "hostile_run", "not_json_run"}) {
    fs::create_directories(t / run);
    write(t / run / "scene.json", box_record.dump());
  }
  write(t / "garbage_run" / "model.clr", random_bytes(4096, 8));
  nn::Checkpoint c;
  c.config_json = nn::to_json(nn::NetworkConfig{}).dump();
  c.tensors.emplace_back("mlp.params", std::vector<float>(1000, 0.0f));
  nn::write_checkpoint((t / "truncated_run" / "model.clr").string(), c);
  const std::string whole = read(t / "truncated_run" / "model.clr");
  write(t / "truncated_run" / "model.clr", whole.substr(0, whole.size() - 100));
  // A valid file whose config asks for the largest network the config rules allow, but holds no parameters.
  nn::NetworkConfig big;
  big.encoder.grid->levels = 16;
  big.encoder.grid->features = 8;
  big.encoder.grid->log2_table = 24;
  big.width = 4096;
  big.hidden_layers = 64;
  big.outputs = 3;  // an N-Module's: the tensors' check, not the shape's, is what refuses it
  c.config_json = nn::to_json(big).dump();
  c.tensors.clear();
  nn::write_checkpoint((t / "hostile_run" / "model.clr").string(), c);
  c.config_json = "{\"width\": ";
  nn::write_checkpoint((t / "not_json_run" / "model.clr").string(), c);

  {  // the bundled box with its camera, then a shape, moved far beyond what float rays resolve
    std::string box = read(kBox);
    const std::string origin = "origin=\"0, 1, 6.8\"";
    box.replace(box.find(origin), origin.size(), "origin=\"3e38, 1, 6.8\"");
    write(t / "far_sensor.xml", box);
    write(t / "far_vertex.xml", R"(<scene version="3.0.0"><shape type="rectangle"><transform name="to_world">)"
                                R"(<translate x="1e30"/></transform></shape></scene>)");
  }
  fs::copy_file(kBox, t / "box_copy.xml");
  // Folders named as image outputs, extension and all: refused as folders.
  fs::create_directories(t / "dir.exr");
  fs::create_directories(t / "dir.png");
  fs::create_directories(t / "sweep_holds_scene");
  fs::copy_file(kBox, t / "sweep_holds_scene" / "tables.md");
  fs::create_symlink(t / "box_copy.xml", t / "box_link.exr");
  // JSON: deeply nested, a 10 MB value, unknown keys inside the modules' patches, integers that would wrap.
  write(t / "deep.json", "{\"network\": " + std::string(100000, '[') + std::string(100000, ']') + "}");
  write(t / "huge_value.json", "{\"method\": \"" + std::string(10 << 20, 'x') + "\"}");
  write(t / "nested_unknown.json", R"({"network": {"widht": 64}})");
  write(t / "guide_unknown.json", R"({"guide": {"encoder": {"grid": {"levles": 4}}}})");
  write(t / "batch_wraps.json", R"({"batch": 4294967808})");
  write(t / "seed_negative.json", R"({"seed": -1})");
  // FIFOs where a file is read: opening one for reading would block until a writer came.
  ::mkfifo((t / "fifo").c_str(), 0600);
  write(t / "newline_type.xml", scene_around("<shape type=\"te&#10;apot\"/>"));
  write(t / "escape_type.xml", scene_around("<shape type=\"&#27;[31mred\"/>"));
  fs::copy_file(kBox, t / "box\xff.xml");
  fs::create_directories(t / "fifo_run");
  write(t / "fifo_run" / "scene.json", box_record.dump());
  ::mkfifo((t / "fifo_run" / "model.clr").c_str(), 0600);
  // Run directories to resume whose own files are bad (the checkpoint itself is never reached).
  for (const char* run : {"fifo_config_run", "malformed_config_run", "nan_log_run"}) {
    fs::create_directories(t / run);
    write(t / run / "model.clr", "x");
    write(t / run / "config.json", "{}");
    write(t / run / "log.csv", "step,seconds\n");
  }
  fs::remove(t / "fifo_config_run" / "config.json");
  ::mkfifo((t / "fifo_config_run" / "config.json").c_str(), 0600);
  write(t / "malformed_config_run" / "config.json", "{\"method\": ");
  write(t / "nan_log_run" / "log.csv", "step,seconds\n25,nan,0.1\n");
}

// The generated inputs take seconds to make, and ctest runs every case in a process of its own (some 190 of them):
// they are made once per test binary (its path and modification time name the folder), under a lock that parallel
// ctest processes share, and each process works in its own folder of hard links to them. Commands replace their
// outputs (common/atomic_file.hpp) rather than write into an existing file, so no case changes a shared input.
fs::path generated_once() {
  const fs::path exe = fs::read_symlink("/proc/self/exe");
  const fs::path base =
      fs::temp_directory_path() / ("clr_corpus_inputs_" + std::to_string(std::hash<std::string>{}(exe.string())) + "_" +
                                   std::to_string(fs::last_write_time(exe).time_since_epoch().count()));
  const std::string lock = base.string() + ".lock";
  const int fd = ::open(lock.c_str(), O_CREAT | O_RDWR, 0600);
  if (fd < 0 || ::flock(fd, LOCK_EX) != 0) throw std::runtime_error("cannot lock " + lock);
  if (!fs::exists(base / ".complete")) {
    // Folders of earlier builds of this binary (same path, another time) are stale.
    const std::string prefix = base.filename().string().substr(0, base.filename().string().rfind('_') + 1);
    for (const auto& e : fs::directory_iterator(base.parent_path()))
      if (const std::string name = e.path().filename().string();
          name.starts_with(prefix) && e.path() != base && e.path().string() != lock)
        fs::remove_all(e.path());
    fs::remove_all(base);
    fs::create_directories(base);
    generate(base);
    write(base / ".complete", "");
  }
  ::close(fd);  // releases the lock
  return base;
}

void link_tree(const fs::path& from, const fs::path& to) {
  fs::create_directories(to);
  for (const auto& e : fs::recursive_directory_iterator(from)) {
    const fs::path target = to / e.path().lexically_relative(from);  // fs::relative would follow links
    if (e.is_directory() && !e.is_symlink())
      fs::create_directories(target);
    else
      fs::create_hard_link(e.path(), target);  // link(2): FIFOs and symbolic links themselves, not their targets
  }
}

// This process's folder of the generated inputs, made on first use and removed at exit. Not in SetUpTestSuite: gtest
// reports the tests of a suite whose set-up failed as skipped, and ctest would count them as skipped, not failed;
// here a failure fails the test that needed the folder.
const fs::path& corpus_dir() {
  struct Folder {
    fs::path path = fs::temp_directory_path() / ("clr_corpus_" + std::to_string(::getpid()));
    Folder() {
      fs::remove_all(path);
      link_tree(generated_once(), path);
    }
    ~Folder() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  };
  static const Folder folder;
  return folder.path;
}

class BadInputCorpus : public ::testing::TestWithParam<Case> {};

std::string expand(std::string s, const fs::path& t) {
  for (const auto& [key, value] :
       {std::pair<std::string, std::string>{"{c}", kCorpus.string()}, {"{t}", t.string()}, {"{box}", kBox.string()}})
    for (auto at = s.find(key); at != std::string::npos; at = s.find(key, at + value.size()))
      s.replace(at, key.size(), value);
  return s;
}

TEST_P(BadInputCorpus, ExitsWithOneClearLine) {
  const Case& c = GetParam();
  const bool needs_device =
      c.args.starts_with("train") || c.args.starts_with("render") || c.args.starts_with("residual");
  if (needs_device && cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL device";
  const fs::path& dir = corpus_dir();
  fs::remove(dir / "out.exr");
  fs::remove_all(dir / "run");
  const auto r = run_limited(expand(c.args, dir), dir);
  EXPECT_EQ(r.exit_code, c.exit_code) << c.args << "\n" << r.err;
  if (c.exit_code == 0) return;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_LT(r.err.size(), 1024u) << "an error line echoed its input whole";
  EXPECT_THAT(r.err, HasSubstr(c.fragment));
  EXPECT_FALSE(fs::exists(dir / "out.exr")) << "a failed command left an output";
  EXPECT_FALSE(fs::exists(dir / "run" / "model.clr")) << "a refused training left a checkpoint";
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadInputCorpus, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& param) {
                           std::string name = param.param.name;
                           for (auto& ch : name)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return name;
                         });

// Writing to a device must write through it, not replace it (common/atomic_file.hpp).
TEST(BadInputCorpusOutput, DevNullStaysADevice) {
  ASSERT_TRUE(fs::is_character_file("/dev/null"));
  const auto r = run_limited("reference '" + kBox.string() + "' --spp 1 --width 4 --height 4 -o /dev/null",
                             fs::temp_directory_path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_character_file("/dev/null")) << "/dev/null was replaced by a regular file";
}

// An output FIFO that no process reads ends the command with its line (found when the output is written: opening a
// FIFO to test it would end a reader's input early), instead of waiting for a reader forever.
TEST(BadInputCorpusOutput, OutputFifoWithoutReaderEnds) {
  const fs::path dir = fs::temp_directory_path() / ("clr_out_fifo_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_EQ(::mkfifo((dir / "out.exr").c_str(), 0600), 0);
  const auto r = run_limited(
      "reference '" + kBox.string() + "' --spp 1 --width 4 --height 4 -o '" + (dir / "out.exr").string() + "'", dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("is a FIFO that no process read within"));
  EXPECT_TRUE(fs::is_fifo(dir / "out.exr"));
  fs::remove_all(dir);
}

// Warnings echo the scene's values too, and are terminal-safe as errors are: an escape sequence in a property's
// name (a Mitsuba 0.x scene only warns about it) is shown escaped, never sent to the terminal.
TEST(BadInputCorpusOutput, WarningsAreTerminalSafe) {
  const fs::path dir = fs::temp_directory_path() / ("clr_warning_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  write(dir / "scene.xml",
        "<scene version=\"0.6.0\"><sensor type=\"perspective\"/><shape type=\"rectangle\">"
        "<float name=\"odd&#27;[1mname\" value=\"1\"/><emitter type=\"area\"/></shape></scene>");
  const auto r = run_limited("reference '" + (dir / "scene.xml").string() + "' --spp 1 --width 4 --height 4 -o '" +
                                 (dir / "out.exr").string() + "'",
                             dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("unused property 'odd\\x1b[1mname'"));
  EXPECT_EQ(r.err.find('\x1b'), std::string::npos) << "a raw escape reached the terminal";
  fs::remove_all(dir);
}

// PoCL's kernel cache as it is now, so that a test that changes XDG_CACHE_HOME does not recompile every kernel.
std::string pocl_cache() {
  if (const char* dir = std::getenv("POCL_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return (fs::path(xdg) / "pocl").string();
  if (const char* home = std::getenv("HOME"); home && *home) return (fs::path(home) / ".cache" / "pocl").string();
  return "";
}

// A FIFO where the GEMM probe cache is kept is neither read nor written (writing through it blocked `train` for
// good before its first step): the run trains, the FIFO stays.
TEST(BadInputCorpusOutput, ProbeCacheFifoIsNotWrittenThrough) {
  if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL device";
  const fs::path dir = fs::temp_directory_path() / ("clr_probe_fifo_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "xdg" / "clradiosity");
  const fs::path fifo = dir / "xdg" / "clradiosity" / "gemm_probe.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto r =
      run_limited("train '" + kBox.string() + "' --steps 1 --batch 256 -o '" + (dir / "run").string() + "'", dir,
                  "XDG_CACHE_HOME='" + (dir / "xdg").string() + "' POCL_CACHE_DIR='" + pocl_cache() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_fifo(fifo));
  fs::remove_all(dir);
}

// An unusable PoCL kernel cache folder is named before any kernel is built (PoCL registers its platform anyway and
// then fails every build with an empty log).
TEST(BadInputCorpusOutput, UnusablePoclCacheIsNamed) {
  bool pocl = false;
  for (const auto& d : cl::list_devices())
    pocl = pocl || d.platform_name.find("Portable Computing Language") != std::string::npos;
  if (!pocl) GTEST_SKIP() << "no PoCL device";
  const fs::path dir = fs::temp_directory_path() / ("clr_pocl_cache_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  write(dir / "a_file", "x");
  const auto r =
      run_limited("train '" + kBox.string() + "' --device pocl --steps 1 -o '" + (dir / "run").string() + "'", dir,
                  "POCL_CACHE_DIR='" + (dir / "a_file").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("kernel cache folder is not usable"));
  EXPECT_THAT(r.err, HasSubstr((dir / "a_file").string()));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace clr::test
