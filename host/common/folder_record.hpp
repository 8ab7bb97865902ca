#pragma once
// What defines the contents of an output folder that a rerun continues (a sweep's rows, a camera path's frames):
// recorded in a JSON file there by the first run; a rerun with other values would mix results made two ways in one
// folder, so it is refused naming the option that changed.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace clr {

// Writes `record` to `file` when there is none; else InputError "<folder> holds <what> made with other settings:
// <option> was …, now …" for the first key whose value differs. `options` names each key's option for the message.
// `content` names what the folder already holds that the record describes ("" when it holds none of it): content
// without its record cannot be matched to any settings, so it is refused rather than adopted under these.
void require_same_record(const std::filesystem::path& file, const nlohmann::json& record, const std::string& what,
                         const std::map<std::string, std::string>& options, const std::string& content = "");

}  // namespace clr
