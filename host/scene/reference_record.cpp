#include "scene/reference_record.hpp"

#include "common/error.hpp"
#include "common/input_file.hpp"

namespace clr::scene {

std::map<std::string, std::string> reference_record(const std::string& scene_digest, const Camera& camera, int sensor,
                                                    int max_depth, std::uint64_t seed) {
  return {{"sceneDigest", scene_digest},
          {"sensor", std::to_string(sensor)},
          {"size", std::to_string(camera.width) + "x" + std::to_string(camera.height)},
          {"maxDepth", std::to_string(max_depth)},
          {"pixelFilter", camera.filter.describe()},
          {"seed", std::to_string(seed)}};
}

std::string check_reference_record(const std::map<std::string, std::string>& attributes,
                                   const std::string& scene_digest, int sensor, const std::string& option,
                                   const std::string& file) {
  const auto recorded = [&](const char* key) {
    const auto it = attributes.find(key);
    return it == attributes.end() ? std::string() : it->second;
  };
  const std::string where = option + " " + file + ": ";
  if (const std::string digest = recorded("sceneDigest"); !digest.empty() && digest != scene_digest)
    throw InputError(where + "it was rendered from another scene (digest " + clip(digest) + ", this scene's " +
                     scene_digest + ": other files or -D parameters)");
  if (const std::string other = recorded("sensor"); sensor >= 0 && !other.empty() && other != std::to_string(sensor))
    throw InputError(where + "it was rendered from sensor " + clip(other) + ", this command's is " +
                     std::to_string(sensor) + " (--sensor)");
  if (const std::string depth = recorded("maxDepth"); !depth.empty() && depth != "-1")
    return where + "it holds paths of at most " + clip(depth) +
           " segments (the scene's integrator, or --max-depth), the model the whole transport: render it with "
           "`reference --max-depth -1` to compare like with like";
  return "";
}

}  // namespace clr::scene
