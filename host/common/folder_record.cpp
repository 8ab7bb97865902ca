#include "common/folder_record.hpp"

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"

namespace clr {

void require_same_record(const std::filesystem::path& file, const nlohmann::json& record, const std::string& what,
                         const std::map<std::string, std::string>& options, const std::string& content) {
  if (!std::filesystem::exists(file) && !std::filesystem::is_symlink(file)) {
    if (!content.empty())
      throw InputError(file.parent_path().string() + " holds " + content + " but no record of the settings they were " +
                       "made with (" + file.filename().string() + "): they cannot be continued; use another folder");
    write_record_atomically(file, record.dump(2) + "\n", what + " record");
    return;
  }
  const nlohmann::json recorded = read_json_file(file, what + " record");
  for (const auto& [key, value] : record.items())
    if (!recorded.is_object() || !recorded.contains(key) || recorded.at(key) != value) {
      const auto option = options.find(key);
      throw InputError(file.parent_path().string() + " holds " + what +
                       " made with other settings: " + (option == options.end() ? key : option->second) + " was " +
                       clip(recorded.is_object() && recorded.contains(key) ? recorded.at(key).dump() : "absent") +
                       ", now " + clip(value.dump()) + " (" + file.string() +
                       "); results made both ways would share one folder: use another");
    }
}

}  // namespace clr
