#include "common/input_file.hpp"

#include <fstream>
#include <iterator>

#include "common/error.hpp"

namespace clr {
namespace fs = std::filesystem;

void require_regular_file(const fs::path& path, const std::string& what) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (!fs::exists(status)) throw InputError(what + " " + clip(path.string()) + " not found");
  if (!fs::is_regular_file(status)) throw InputError(what + " " + clip(path.string()) + " is not a regular file");
}

std::string read_input_text(const fs::path& path, const std::string& what) {
  require_regular_file(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot read " + what + " " + clip(path.string()));
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

nlohmann::json parse_json(std::string_view text, const std::string& what) {
  // The depth is found by one pass over the text before parsing, not by a parser callback: nlohmann's callback
  // parser builds and copies values for every event, which made a 53 MB camera path take minutes. The pass counts
  // brackets outside strings; a malformed text that it misjudges is refused by the parser that follows.
  int depth = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw InputError(what + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  try {
    return nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::exception& e) {
    throw InputError("malformed JSON in " + what + ": " + clip(e.what(), 200));
  }
}

nlohmann::json read_json_file(const fs::path& path, const std::string& what) {
  return parse_json(read_input_text(path, what), what + " " + clip(path.string()));
}

namespace {

// Integers compare by sign and magnitude: nlohmann's own comparison would cast −1 to 2^64 − 1.
bool same_integer(const nlohmann::json& a, const nlohmann::json& b) {
  const auto sign_magnitude = [](const nlohmann::json& x) -> std::pair<bool, unsigned long long> {
    if (x.is_number_unsigned()) return {false, x.get<unsigned long long>()};
    const long long v = x.get<long long>();
    return {v < 0, v < 0 ? 0ull - static_cast<unsigned long long>(v) : static_cast<unsigned long long>(v)};
  };
  return sign_magnitude(a) == sign_magnitude(b);
}

void walk(const nlohmann::json& given, const nlohmann::json& parsed, const std::string& at, const std::string& what) {
  for (const auto& [key, value] : given.items()) {
    const std::string name = at + clip(key);
    if (!parsed.is_object() || !parsed.contains(key)) throw InputError(what + ": unknown key '" + name + "'");
    const auto& kept = parsed.at(key);
    if (value.is_object() && kept.is_object()) walk(value, kept, name + ".", what);
    const bool kept_ok = !value.is_number_integer() ||
                         (kept.is_number_integer() ? same_integer(value, kept)
                                                   : kept.is_number() && value.get<double>() == kept.get<double>());
    if (!kept_ok) throw InputError(what + ": '" + name + "' " + clip(value.dump()) + " is out of range");
  }
}

}  // namespace

void require_known_and_kept(const nlohmann::json& given, const nlohmann::json& parsed, const std::string& what) {
  if (given.is_object()) walk(given, parsed, "", what);
}

std::string clip(std::string_view text, std::size_t max) {
  if (text.size() <= max) return std::string(text);
  return std::string(text.substr(0, max)) + "… (" + std::to_string(text.size()) + " bytes)";
}

}  // namespace clr
