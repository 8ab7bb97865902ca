#include "scene/memory_budget.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "common/error.hpp"
#include "common/terminal_text.hpp"

namespace clr::scene {
namespace {

constexpr const char* kVariable = "CLRADIOSITY_MEMORY_LIMIT";

std::uint64_t parse_size(const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  std::string suffix(end);
  if (!suffix.empty() && (suffix.back() == 'B' || suffix.back() == 'b')) suffix.pop_back();
  if (suffix.size() == 2 && suffix[1] == 'i') suffix.pop_back();
  double unit = 0;
  if (suffix.empty())
    unit = 1;
  else if (suffix.size() == 1)
    switch (suffix[0]) {
      case 'k':
      case 'K':
        unit = 0x1p10;
        break;
      case 'm':
      case 'M':
        unit = 0x1p20;
        break;
      case 'g':
      case 'G':
        unit = 0x1p30;
        break;
      case 't':
      case 'T':
        unit = 0x1p40;
        break;
      default:
        break;
    }
  const double bytes = value * unit;
  if (end == text.c_str() || !(unit > 0) || !(bytes >= 1) || !(bytes < 0x1p63))
    throw InputError(std::string(kVariable) + "='" + terminal_safe(text) +
                     "' is no memory size (bytes, or a number with K, M, G or T, e.g. 16G)");
  return std::uint64_t(bytes);
}

}  // namespace

std::string human_bytes(std::uint64_t bytes) {
  char buf[32];
  if (bytes >= (std::uint64_t(1) << 30))
    std::snprintf(buf, sizeof buf, "%.1f GB", double(bytes) / 0x1p30);
  else if (bytes >= (std::uint64_t(1) << 20))
    std::snprintf(buf, sizeof buf, "%.0f MB", double(bytes) / 0x1p20);
  else
    return "under 1 MB";
  return buf;
}

MemoryBudget::MemoryBudget() {
  if (const char* env = std::getenv(kVariable); env && *env) {
    limit_ = parse_size(env);
    from_environment_ = true;
    return;
  }
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  // Unknown: no limit but the allocator's.
  limit_ = pages > 0 && page > 0 ? std::uint64_t(pages) * std::uint64_t(page) / 4 * 3 : UINT64_MAX;
}

void MemoryBudget::require(std::uint64_t bytes, Part part, const std::string& what) const {
  const std::uint64_t geometry = used_[0] + (part == Part::geometry ? bytes : 0),
                      images = used_[1] + (part == Part::images ? bytes : 0);
  // Compared part by part first: a hostile count can be near 2^64, and the sum must not wrap.
  if (geometry <= limit_ && images <= limit_ && geometry + images <= limit_ && geometry >= used_[0] &&
      images >= used_[1])
    return;
  const bool wrapped = geometry < used_[0] || images < used_[1];
  throw InputError(what + " would bring the scene to " +
                   (wrapped ? std::string("more memory than can be counted")
                            : "about " + human_bytes(geometry + images) + " of memory (geometry " +
                                  human_bytes(geometry) + ", images " + human_bytes(images) + ")") +
                   ", more than its limit of " + human_bytes(limit_) +
                   (from_environment_
                        ? std::string(" (") + kVariable + ")"
                        : std::string(" (three quarters of this machine's memory; ") + kVariable + " sets another)"));
}

void MemoryBudget::charge(std::uint64_t bytes, Part part, const std::string& what) {
  require(bytes, part, what);
  used_[part == Part::geometry ? 0 : 1] += bytes;
}

}  // namespace clr::scene
