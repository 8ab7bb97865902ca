#include "scene/shapes/ply_attributes.hpp"

#include <algorithm>
#include <array>
#include <set>

namespace clr::scene {
namespace {

// The postfix sequences a multi-channel attribute may follow; the second is a colour's.
constexpr const char* kSequences[] = {"xyzw", "rgba", "0123", "1234"};
constexpr std::size_t kColorSequence = 1;

std::size_t find(const std::vector<std::string>& names, const char* name) {
  return std::size_t(std::find(names.begin(), names.end(), name) - names.begin());
}

}  // namespace

std::vector<PlyAttribute> ply_attributes(const std::string& element, const std::vector<std::string>& names) {
  std::vector<PlyAttribute> out;
  // The colour, spelt r g b [a] or (when those are not all there) red green blue [alpha].
  for (const auto& spelling : {std::array<const char*, 4>{"r", "g", "b", "a"}, {"red", "green", "blue", "alpha"}}) {
    const std::size_t r = find(names, spelling[0]), g = find(names, spelling[1]), b = find(names, spelling[2]);
    if (std::max({r, g, b}) == names.size()) continue;
    PlyAttribute color{element + "_color", {r, g, b}};
    if (const std::size_t a = find(names, spelling[3]); a < names.size()) color.properties.push_back(a);
    out.push_back(std::move(color));
    break;
  }

  std::set<std::string> seen;  // prefixes already read (or rejected): each names one attribute at most
  std::string prefix;          // the attribute being read; empty: none
  std::size_t sequence = 0;
  std::vector<std::size_t> channels;
  auto flush = [&] {
    if (!prefix.empty() && (channels.size() == 1 || channels.size() == 3))
      out.push_back({element + "_" + prefix + (sequence == kColorSequence ? "_color" : ""), channels});
    if (!prefix.empty()) seen.insert(prefix);
    prefix.clear();
    channels.clear();
  };
  static const std::set<std::string> kColorNames{"r", "g", "b", "a", "red", "green", "blue", "alpha"};
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string& name = names[i];
    if (name.empty() || kColorNames.count(name)) continue;
    const std::size_t underscore = name.rfind('_');
    if (underscore == std::string::npos || underscore + 2 != name.size()) {
      flush();  // no one-letter postfix: no attribute, and the end of the one being read
      continue;
    }
    const std::string p = name.substr(0, underscore);
    const char postfix = name.back();
    if (p != prefix) flush();
    if (prefix.empty()) {
      if (seen.count(p)) continue;
      sequence = 0;
      while (sequence < 4 && kSequences[sequence][0] != postfix) ++sequence;
      if (sequence == 4) continue;  // starts no sequence
      prefix = p;
    } else if (channels.size() == 4 || kSequences[sequence][channels.size()] != postfix) {
      channels.clear();  // a broken sequence: the whole attribute is ignored
      flush();
      continue;
    }
    channels.push_back(i);
  }
  flush();
  return out;
}

}  // namespace clr::scene
