#include "scene/fingerprint.hpp"

#include <algorithm>

#include "common/digest.hpp"

namespace clr::scene {
namespace fs = std::filesystem;

std::string files_digest(const std::vector<SceneFingerprint::File>& files,
                         const std::map<std::string, std::string>& parameters) {
  Digest all;
  // The scene file is named by its position: a renamed scene.xml with the same content is the same scene.
  for (std::size_t i = 0; i < files.size(); ++i)
    all.add(i == 0 ? "" : files[i].name).add("\n").add(files[i].digest).add("\n");
  // Added only where there are any, so a scene loaded without -D keeps the digest runs recorded before -D existed.
  for (const auto& [name, value] : parameters) all.add("-D ").add(name).add("=").add(value).add("\n");
  return all.hex();
}

SceneFingerprint fingerprint(const Scene& scene) {
  SceneFingerprint f;
  if (scene.files.empty()) return f;
  f.scene = scene.files.front();
  const fs::path folder = fs::absolute(f.scene).lexically_normal().parent_path();
  for (std::size_t i = 0; i < scene.files.size(); ++i) {
    const fs::path absolute = fs::absolute(scene.files[i]).lexically_normal();
    const fs::path relative = absolute.lexically_relative(folder);
    const bool inside = !relative.empty() && *relative.begin() != "..";
    f.files.push_back({(inside ? relative : absolute).generic_string(), scene.file_digests.at(i)});
  }
  f.parameters = scene.parameters;
  f.digest = files_digest(f.files, f.parameters);
  return f;
}

std::string difference(const SceneFingerprint& from, const SceneFingerprint& to) {
  if (from.digest == to.digest) return "";
  if (from.parameters != to.parameters) {
    const auto list = [](const std::map<std::string, std::string>& p) {
      std::string s;
      for (const auto& [name, value] : p) s += (s.empty() ? "" : " ") + name + "=" + value;
      return s.empty() ? std::string("none") : s;
    };
    return "the parameters differ (-D " + list(from.parameters) + " then, " + list(to.parameters) + " now)";
  }
  if (!from.files.empty() && !to.files.empty() && from.files.front().digest != to.files.front().digest)
    return "the scene file differs";
  const auto find = [](const SceneFingerprint& f, const std::string& name) {
    return std::find_if(f.files.begin(), f.files.end(), [&](const auto& e) { return e.name == name; });
  };
  for (std::size_t i = 1; i < to.files.size(); ++i) {
    const auto other = find(from, to.files[i].name);
    if (other == from.files.end()) return to.files[i].name + " is read now, not then";
    if (other->digest != to.files[i].digest) return to.files[i].name + " differs";
  }
  for (std::size_t i = 1; i < from.files.size(); ++i)
    if (find(to, from.files[i].name) == to.files.end()) return from.files[i].name + " was read then, not now";
  return "the files are read in another order";
}

}  // namespace clr::scene
