#include "report/half_image.hpp"

#include <Imath/half.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace clr::report {

std::string base64(std::string_view bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v = std::uint32_t(std::uint8_t(bytes[i])) << 16 |
                            std::uint32_t(std::uint8_t(bytes[i + 1])) << 8 | std::uint32_t(std::uint8_t(bytes[i + 2]));
    for (int s = 18; s >= 0; s -= 6) out += kAlphabet[(v >> s) & 63];
  }
  if (const std::size_t rest = bytes.size() - i; rest > 0) {
    std::uint32_t v = std::uint32_t(std::uint8_t(bytes[i])) << 16;
    if (rest == 2) v |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += rest == 2 ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

std::string halves(const float* values, std::size_t count, std::size_t stride) {
  constexpr float kHalfMax = 65504.0f;
  std::vector<Bytef> planes(count * 2);
  for (std::size_t i = 0; i < count; ++i) {
    const float v = values[i * stride];
    const Imath::half h(std::isnan(v) ? v : std::clamp(v, -kHalfMax, kHalfMax));
    const std::uint16_t bits = h.bits();
    planes[i] = Bytef(bits >> 8);
    planes[count + i] = Bytef(bits & 0xff);
  }
  uLongf size = compressBound(uLong(planes.size()));
  std::vector<Bytef> packed(size);
  if (compress2(packed.data(), &size, planes.data(), uLong(planes.size()), 6) != Z_OK)
    throw std::runtime_error("zlib could not compress a report image");
  return base64(std::string_view(reinterpret_cast<const char*>(packed.data()), size));
}

}  // namespace

std::string half_base64(const image::Image& img) { return halves(img.rgb.data(), img.rgb.size(), 1); }

std::string half_base64_red(const image::Image& img) { return halves(img.rgb.data(), img.rgb.size() / 3, 3); }

}  // namespace clr::report
