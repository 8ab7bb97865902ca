// EXR via OpenEXR, 8/16-bit formats via stb; every write is atomic (common/atomic_file.hpp).
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "image/image.hpp"

namespace clr::image {
namespace fs = std::filesystem;
namespace {

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }
float linear_to_srgb(float c) { return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f; }

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

Image read_exr(const fs::path& path) {
  if (!fs::exists(path)) throw InputError("image file not found: " + path.string());
  if (!fs::is_regular_file(path)) throw InputError("image file is not a regular file: " + path.string());
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    // In 64 bits: a hostile header's window may span more than an int.
    check_image_size(1LL + dw.max.x - dw.min.x, 1LL + dw.max.y - dw.min.y, "EXR " + path.string());
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    const auto& channels = file.header().channels();
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
  int w = 0, h = 0, n = 0;
  if (!stbi_info(path.c_str(), &w, &h, &n) || !stbi_is_hdr(path.c_str()))
    throw InputError("cannot read Radiance HDR image " + path.string());
  check_image_size(w, h, "image " + path.string());
  std::unique_ptr<float, void (*)(void*)> data(stbi_loadf(path.c_str(), &w, &h, &n, 3), stbi_image_free);
  if (!data) throw InputError("cannot read image " + path.string() + ": " + stbi_failure_reason());
  Image img(w, h);
  std::copy_n(data.get(), img.rgb.size(), img.rgb.begin());
  return img;
}

Image read_float_image(const fs::path& path) {
  auto ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".hdr" ? read_hdr(path) : read_exr(path);
}

Image read_ldr(const fs::path& path, bool srgb) {
  if (!fs::exists(path)) throw InputError("image file not found: " + path.string());
  if (!fs::is_regular_file(path)) throw InputError("image file is not a regular file: " + path.string());
  int w = 0, h = 0, n = 0;
  // The header first: stb would otherwise allocate whatever size it announces (up to 1 GiB) before decoding.
  if (!stbi_info(path.c_str(), &w, &h, &n))
    throw InputError("cannot read image " + path.string() + ": " + stbi_failure_reason());
  check_image_size(w, h, "image " + path.string());
  const bool wide = stbi_is_16_bit(path.c_str());
  std::unique_ptr<void, void (*)(void*)> data(wide ? static_cast<void*>(stbi_load_16(path.c_str(), &w, &h, &n, 3))
                                                   : static_cast<void*>(stbi_load(path.c_str(), &w, &h, &n, 3)),
                                              stbi_image_free);
  if (!data) throw InputError("cannot read image " + path.string() + ": " + stbi_failure_reason());
  Image img(w, h);
  const float max = wide ? 65535.0f : 255.0f;
  for (std::size_t i = 0; i < img.rgb.size(); ++i) {
    const float v =
        (wide ? static_cast<const unsigned short*>(data.get())[i] : static_cast<const unsigned char*>(data.get())[i]) /
        max;
    img.rgb[i] = srgb ? srgb_to_linear(v) : v;
  }
  return img;
}

}  // namespace clr::image
