#pragma once
// Modes are enums inside the program; their names exist only where they meet text (command line, config and run
// files, messages). Each mode keeps one table of {value, name} pairs, which both directions read.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace clr {

template <typename E, std::size_t N>
using EnumNames = std::pair<E, const char*>[N];

template <typename E, std::size_t N>
const char* name_of(E value, const EnumNames<E, N>& names) {
  for (const auto& [v, name] : names)
    if (v == value) return name;
  return "?";
}

template <typename E, std::size_t N>
std::optional<E> value_named(std::string_view text, const EnumNames<E, N>& names) {
  for (const auto& [value, name] : names)
    if (text == name) return value;
  return std::nullopt;
}

// "isnr or nr": the names a message lists as the choices.
template <typename E, std::size_t N>
std::string choices(const EnumNames<E, N>& names) {
  std::string text;
  for (std::size_t i = 0; i < N; ++i) text += (i == 0 ? "" : i + 1 == N ? " or " : ", ") + std::string(names[i].second);
  return text;
}

}  // namespace clr
