// EXR via OpenEXR, 8/16-bit formats via stb; every write is atomic (common/atomic_file.hpp).
#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "image/image.hpp"
#include "image/srgb.hpp"

namespace clr::image {
namespace fs = std::filesystem;
namespace {

// The file's bytes, read whole (images are bounded by kMaxPixels and their own size by the disk).
std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// zlib's best ratio (deflate of runs), the bound for every zlib-compressed format below.
constexpr std::uint64_t kZlibMaxRatio = 1032;

// A header announcing more pixels than the file's bytes can encode (`fewest`, from its format's best compression)
// is refused before its pixels are allocated.
void require_bytes(const std::string& what, int w, int h, std::uint64_t size, std::uint64_t fewest) {
  if (size < fewest)
    throw InputError(what + ": its header announces " + std::to_string(w) + "x" + std::to_string(h) +
                     " pixels, more than its " + std::to_string(size) + " bytes can hold (at least " +
                     std::to_string(fewest) + ")");
}

// The fewest bytes a file of `w` × `h` pixels in its format can hold, from the format's best compression: a header
// that announces more pixels than its bytes can encode is refused before its pixels are allocated (a 116-byte
// .hdr announcing 16384 × 8192 would otherwise cost 1.5 GiB). Formats without a useful bound give 0 (their size
// is bounded by kMaxPixels alone).
std::uint64_t fewest_bytes(const std::string& bytes, long long w, long long h) {
  const auto W = std::uint64_t(w), H = std::uint64_t(h);
  if (bytes.starts_with("#?")) {
    // Radiance RGBE as stb reads it: a run-length scanline (widths 8 to 32767) is a 4-byte marker and, for each of
    // its 4 channels, runs of at most 127 bytes of 2 bytes each; any other scanline is 4 bytes a pixel.
    const std::uint64_t rle = 4 + 4 * 2 * ((W + 126) / 127);
    return H * (w >= 8 && w < 32768 ? std::min(rle, 4 * W) : 4 * W);
  }
  if (bytes.starts_with("\x89PNG")) {
    // At least one bit a pixel and a filter byte a row, deflated at most 1032:1 (zlib's limit).
    return H * (1 + (W + 7) / 8) / kZlibMaxRatio;
  }
  if (bytes.starts_with("P5") || bytes.starts_with("P6")) return W * H * (bytes[1] == '6' ? 3 : 1);  // raw PNM
  return 0;
}

// stb reads past a file's end as zeros without a word, so a truncated image would load with black rows: stb reads
// through these callbacks, which note any read that finds the file exhausted.
struct StbSource {
  const std::string& bytes;
  std::size_t at = 0;
  bool starved = false;

  static int read(void* user, char* data, int size) {
    auto& s = *static_cast<StbSource*>(user);
    const std::size_t n = std::min(std::size_t(size), s.bytes.size() - s.at);
    if (n == 0 && size > 0) s.starved = true;
    std::copy_n(s.bytes.data() + s.at, n, data);
    s.at += n;
    return int(n);
  }
  static void skip(void* user, int n) {
    auto& s = *static_cast<StbSource*>(user);
    const auto target = std::ptrdiff_t(s.at) + n;
    if (target > std::ptrdiff_t(s.bytes.size())) s.starved = true;
    s.at = std::size_t(std::clamp<std::ptrdiff_t>(target, 0, std::ptrdiff_t(s.bytes.size())));
  }
  static int eof(void* user) {
    auto& s = *static_cast<StbSource*>(user);
    return s.at >= s.bytes.size();
  }
  stbi_io_callbacks callbacks() const { return {&StbSource::read, &StbSource::skip, &StbSource::eof}; }
};

// Header first (stb would otherwise allocate whatever size it announces), then the bytes that size needs.
void check_stb_header(const std::string& bytes, const fs::path& path, int& w, int& h, int& n) {
  if (!stbi_info_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                             int(std::min<std::size_t>(bytes.size(), INT32_MAX)), &w, &h, &n))
    throw InputError("cannot read image " + path.string() + ": " + stbi_failure_reason());
  check_image_size(w, h, "image " + path.string());
  require_bytes("image " + path.string(), w, h, bytes.size(), fewest_bytes(bytes, w, h));
}

void check_not_starved(const StbSource& source, const fs::path& path) {
  if (source.starved)
    throw InputError("image " + path.string() + " is truncated: its " + std::to_string(source.bytes.size()) +
                     " bytes end before the pixels its header announces");
}

}  // namespace

void check_image_size(long long width, long long height, const std::string& what) {
  if (width < 1 || height < 1)
    throw InputError(what + ": image size " + std::to_string(width) + "x" + std::to_string(height) +
                     " is not positive");
  // Divided rather than multiplied: width·height may not fit.
  if (std::size_t(height) > kMaxPixels / std::size_t(width))
    throw InputError(what + ": image size " + std::to_string(width) + "x" + std::to_string(height) +
                     " exceeds the limit of " + std::to_string(kMaxPixels) + " pixels");
}

Image read_exr(const fs::path& path, std::map<std::string, std::string>* attributes) {
  if (!fs::exists(path)) throw InputError("image file not found: " + path.string());
  if (!fs::is_regular_file(path)) throw InputError("image file is not a regular file: " + path.string());
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    // In 64 bits: a hostile header's window may span more than an int.
    check_image_size(1LL + dw.max.x - dw.min.x, 1LL + dw.max.y - dw.min.y, "EXR " + path.string());
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    const auto& channels = file.header().channels();
    {
      // The bytes the window needs, at the compression's best ratio (raw, or zlib's 1032:1 under the zlib and
      // run-length codecs; the wavelet and lossy codecs give no useful bound): a short file announcing a large
      // window is refused before the window is allocated.
      std::uint64_t raw = 0;
      for (auto c = channels.begin(); c != channels.end(); ++c)
        raw += std::uint64_t(c.channel().type == Imf::HALF ? 2 : 4) * std::uint64_t(w) * std::uint64_t(h) /
               std::uint64_t(std::max(1, c.channel().xSampling * c.channel().ySampling));
      const auto compression = file.header().compression();
      const std::uint64_t fewest = compression == Imf::NO_COMPRESSION ? raw
                                   : compression == Imf::RLE_COMPRESSION || compression == Imf::ZIPS_COMPRESSION ||
                                           compression == Imf::ZIP_COMPRESSION
                                       ? raw / kZlibMaxRatio
                                       : 0;
      require_bytes("EXR " + path.string(), w, h, fs::file_size(path), fewest);
    }
    // RGB, or a single luminance channel Y; a missing channel copies the first one.
    const bool luminance = !channels.findChannel("R");
    if (luminance && !channels.findChannel("Y"))
      throw InputError("EXR has neither R/G/B nor Y channels: " + path.string());
    const char* names[3] = {luminance ? "Y" : "R", "G", "B"};
    bool present[3] = {true, !luminance && channels.findChannel("G"), !luminance && channels.findChannel("B")};

    Image img(w, h);
    Imf::FrameBuffer fb;
    const std::size_t xs = 3 * sizeof(float), ys = xs * std::size_t(w);
    // OpenEXR addresses the slice through the data window's origin.
    char* base = reinterpret_cast<char*>(img.rgb.data()) - std::ptrdiff_t(dw.min.x) * std::ptrdiff_t(xs) -
                 std::ptrdiff_t(dw.min.y) * std::ptrdiff_t(ys);
    for (int c = 0; c < 3; ++c)
      if (present[c]) fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    if (attributes)
      for (auto a = file.header().begin(); a != file.header().end(); ++a)
        if (const auto* text = dynamic_cast<const Imf::StringAttribute*>(&a.attribute()))
          (*attributes)[a.name()] = text->value();
    for (std::size_t i = 0; i < img.rgb.size(); i += 3)
      for (int c = 1; c < 3; ++c)
        if (!present[c]) img.rgb[i + std::size_t(c)] = img.rgb[i];
    return img;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read EXR " + path.string() + ": " + e.what());
  }
}

void write_exr(const fs::path& path, const Image& img, const std::map<std::string, std::string>& attributes) {
  clr::write_atomically(path, [&](const fs::path& tmp) {
    Imf::Header header(img.width, img.height);
    for (const auto& [name, value] : attributes) header.insert(name, Imf::StringAttribute(value));
    for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(tmp.c_str(), header);
    Imf::FrameBuffer fb;
    const std::size_t xs = 3 * sizeof(float), ys = xs * std::size_t(img.width);
    auto* base = const_cast<char*>(reinterpret_cast<const char*>(img.rgb.data()));
    fb.insert("R", Imf::Slice(Imf::FLOAT, base, xs, ys));
    fb.insert("G", Imf::Slice(Imf::FLOAT, base + sizeof(float), xs, ys));
    fb.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xs, ys));
    file.setFrameBuffer(fb);
    file.writePixels(img.height);
  });
}

void write_png(const fs::path& path, const Image& img, float exposure) {
  const float scale = std::exp2(exposure);
  std::vector<unsigned char> bytes(img.rgb.size());
  for (std::size_t i = 0; i < img.rgb.size(); ++i) {
    const float v = std::isfinite(img.rgb[i]) ? std::clamp(img.rgb[i] * scale, 0.0f, 1.0f) : 0.0f;
    bytes[i] = static_cast<unsigned char>(std::lround(linear_to_srgb(v) * 255.0f));
  }
  clr::write_atomically(path, [&](const fs::path& tmp) {
    if (!stbi_write_png(tmp.c_str(), img.width, img.height, 3, bytes.data(), img.width * 3))
      throw std::runtime_error("cannot write PNG " + path.string());
  });
}

Image read_hdr(const fs::path& path) {
  if (!fs::exists(path)) throw InputError("image file not found: " + path.string());
  if (!fs::is_regular_file(path)) throw InputError("image file is not a regular file: " + path.string());
  const std::string bytes = file_bytes(path);
  if (!stbi_is_hdr_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                               int(std::min<std::size_t>(bytes.size(), INT32_MAX))))
    throw InputError("cannot read Radiance HDR image " + path.string());
  int w = 0, h = 0, n = 0;
  check_stb_header(bytes, path, w, h, n);
  StbSource source{bytes};
  const auto callbacks = source.callbacks();
  std::unique_ptr<float, void (*)(void*)> data(stbi_loadf_from_callbacks(&callbacks, &source, &w, &h, &n, 3),
                                               stbi_image_free);
  if (!data) throw InputError("cannot read image " + path.string() + ": " + stbi_failure_reason());
  check_not_starved(source, path);
  Image img(w, h);
  std::copy_n(data.get(), img.rgb.size(), img.rgb.begin());
  return img;
}

Image read_float_image(const fs::path& path) {
  auto ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".hdr" ? read_hdr(path) : read_exr(path);
}

std::pair<int, int> image_file_size(const fs::path& path) {
  if (!fs::is_regular_file(path)) throw InputError("image file not found or not a regular file: " + path.string());
  auto ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".exr") {
    try {
      const Imath::Box2i dw = Imf::InputFile(path.c_str()).header().dataWindow();
      check_image_size(1LL + dw.max.x - dw.min.x, 1LL + dw.max.y - dw.min.y, "EXR " + path.string());
      return {dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1};
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      throw InputError("cannot read EXR " + path.string() + ": " + e.what());
    }
  }
  int w = 0, h = 0, n = 0;
  if (!stbi_info(path.c_str(), &w, &h, &n))
    throw InputError("cannot read image " + path.string() + ": " + stbi_failure_reason());
  check_image_size(w, h, "image " + path.string());
  return {w, h};
}

Image read_ldr(const fs::path& path, bool srgb) {
  if (!fs::exists(path)) throw InputError("image file not found: " + path.string());
  if (!fs::is_regular_file(path)) throw InputError("image file is not a regular file: " + path.string());
  const std::string bytes = file_bytes(path);
  int w = 0, h = 0, n = 0;
  check_stb_header(bytes, path, w, h, n);
  const bool wide = stbi_is_16_bit_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                               int(std::min<std::size_t>(bytes.size(), INT32_MAX)));
  StbSource source{bytes};
  const auto callbacks = source.callbacks();
  std::unique_ptr<void, void (*)(void*)> data(
      wide ? static_cast<void*>(stbi_load_16_from_callbacks(&callbacks, &source, &w, &h, &n, 3))
           : static_cast<void*>(stbi_load_from_callbacks(&callbacks, &source, &w, &h, &n, 3)),
      stbi_image_free);
  if (!data) throw InputError("cannot read image " + path.string() + ": " + stbi_failure_reason());
  check_not_starved(source, path);
  Image img(w, h);
  if (wide) {
    const auto* v = static_cast<const unsigned short*>(data.get());
    for (std::size_t i = 0; i < img.rgb.size(); ++i)
      img.rgb[i] = srgb ? srgb_to_linear(v[i] / 65535.0f) : v[i] / 65535.0f;
  } else {
    // A table of the 256 values: a pow a texel was 0.5 of the 1.8 CPU seconds that loading Wooden Staircase took.
    static const std::array<float, 256> from_srgb = [] {
      std::array<float, 256> t{};
      for (int b = 0; b < 256; ++b) t[b] = srgb_to_linear(float(b) / 255.0f);
      return t;
    }();
    const auto* v = static_cast<const unsigned char*>(data.get());
    for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = srgb ? from_srgb[v[i]] : v[i] / 255.0f;
  }
  return img;
}

}  // namespace clr::image
