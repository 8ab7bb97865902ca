#pragma once
// Linear RGB float images, EXR/PNG files and the metrics of docs/design.md §4.
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace clr::image {

// Row-major, top row first, 3 floats (linear RGB) per pixel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(std::size_t(w) * std::size_t(h) * 3, 0.0f) {}
  float* pixel(int x, int y) { return &rgb[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3]; }
  const float* pixel(int x, int y) const { return &rgb[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3]; }
};

// The most pixels an image that any command makes or reads may have: 2^27 (16384 × 8192, a 16K lat-long
// environment map), 1.5 GiB as float RGB. A film, option or file header that announces more is refused as bad
// input before anything is allocated, rather than failing in the allocator (or the OOM killer) halfway through.
inline constexpr std::size_t kMaxPixels = std::size_t(1) << 27;
// InputError "<what>: ..." unless width and height are ≥ 1 and width·height ≤ kMaxPixels.
void check_image_size(long long width, long long height, const std::string& what);

// RGB channels of an OpenEXR file (missing G/B replicate R; alpha ignored). InputError naming the file on failure.
// `attributes`, where given, receives the header's string attributes (write_exr's).
Image read_exr(const std::filesystem::path& path, std::map<std::string, std::string>* attributes = nullptr);
// Writes a float32 RGB EXR, atomically (temp name, then rename), so no partial file is left behind. `attributes`
// become string attributes of its header (what made the image: spp, seconds, seed, …, as pbrt records them).
void write_exr(const std::filesystem::path& path, const Image& img,
               const std::map<std::string, std::string>& attributes = {});
// 8-bit sRGB PNG of the image scaled by 2^exposure and clamped, written atomically.
void write_png(const std::filesystem::path& path, const Image& img, float exposure = 0.0f);
// 8-bit image files (png/jpg/...) as linear or sRGB-decoded floats, for textures.
Image read_ldr(const std::filesystem::path& path, bool srgb_to_linear);
// Radiance RGBE (.hdr) files, linear floats; and whichever of the HDR formats a file name's extension says
// (.hdr, else OpenEXR).
Image read_hdr(const std::filesystem::path& path);
Image read_float_image(const std::filesystem::path& path);
// The width and height an image file's header announces (OpenEXR by a .exr name, else what stb reads), without
// decoding its pixels: what reading it will allocate, for a budget to weigh first. InputError naming the file when
// it is missing or its header unreadable.
std::pair<int, int> image_file_size(const std::filesystem::path& path);

// Averages factor×factor blocks; width and height must be multiples of factor.
Image box_downsample(const Image& img, int factor);
// `ref` resized to `like` when its size is an integer multiple of it; InputError when the sizes do not fit.
Image match_size(const Image& ref, const Image& like);
// match_size's InputError, without the images: for a reference checked before the image it is compared with is made.
void require_matching_size(int ref_width, int ref_height, int width, int height);

struct Metrics {
  double mape = 0;    // mean(|a−b| / (|b| + 0.01))
  double mse = 0;     // mean((a−b)²)
  double relmse = 0;  // mean((a−b)² / (b² + 0.01))
  // Σa / Σb: the image's brightness against the reference's. A model whose scale runs away shows it here first
  // (MAPE saturates near the ratio); 1 is right on average, whatever the per-pixel error.
  double mean_ratio = 1;
  // Values (pixels·channels) of the image under test that are NaN or infinite. A model or renderer that produced
  // them has failed there, and no mean over the rest may hide it: the metrics are then NaN.
  std::size_t non_finite = 0;
  // Non-finite values of the reference: those positions are left out of the means (a reference's fault is not the
  // image's), and counted.
  std::size_t reference_non_finite = 0;
};
// InputError "WHAT: it holds no finite value" for a reference with nothing to measure against (all NaN or
// infinite): every consumer of a reference checks it before its work, and compare() once more.
void require_usable_reference(const Image& ref, const std::string& what);
// Over all pixels and channels; images must have equal size.
Metrics compare(const Image& a, const Image& ref);
// "MAPE …  MSE …  relMSE …", followed by the non-finite counts where there are any.
std::string describe(const Metrics& m);

// Per-pixel relative error |a−b|/(|b|+0.01) (channel mean) as a false-colour map, 0 → blue … ≥ max_error → red.
Image error_map(const Image& a, const Image& ref, float max_error = 1.0f);

}  // namespace clr::image
