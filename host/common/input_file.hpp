#pragma once
// Every file the program reads as input (a scene, a config, a run's files, a checkpoint, an image, a cache) is
// checked here before anything opens it: opening a FIFO for reading blocks until a writer appears, and a device
// such as /dev/zero never ends. JSON inputs are parsed here too, with one nesting limit for all of them, checked
// while parsing — before any code walks the document recursively.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace clr {

// JSON documents nested deeper are refused: no input the program reads needs more than a few levels.
inline constexpr int kMaxJsonDepth = 64;

// InputError "<what> <path> not found" / "… is not a regular file" unless `path` (links followed) is one.
void require_regular_file(const std::filesystem::path& path, const std::string& what);

// The whole file, after require_regular_file.
std::string read_input_text(const std::filesystem::path& path, const std::string& what);

// `text` parsed as JSON; InputError naming `what` when it is malformed or nested deeper than kMaxJsonDepth.
nlohmann::json parse_json(std::string_view text, const std::string& what);
nlohmann::json read_json_file(const std::filesystem::path& path, const std::string& what);

// Strictness all the way down, for a JSON settings object `given` and `parsed`, the same settings after conversion
// to the program's types and back: InputError "<what>: unknown key 'a.b'" for a key (at any depth) that `parsed`
// lacks, and "<what>: 'a.b' … is out of range" for an integer that did not survive the conversion unchanged (2^32 +
// 512 into 32 bits, −1 into an unsigned type).
void require_known_and_kept(const nlohmann::json& given, const nlohmann::json& parsed, const std::string& what);

// At most `max` bytes of `text` for an error line, marked where it was cut: a bad value may be 100 MB long.
std::string clip(std::string_view text, std::size_t max = 80);

}  // namespace clr
