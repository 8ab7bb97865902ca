#pragma once
// What a run, a model or a sweep records of the scene it belongs to, so that using it with another scene is
// refused instead of silently giving that scene's answer with this one's bounding box and inputs: the digest of
// every file the scene read, taken as the loader read it (Scene::files, Scene::file_digests), each named relative
// to the scene's folder. Contents, not paths, decide:
// a scene folder that was copied or moved keeps its runs; a mesh edited in place does not.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace clr::scene {

struct SceneFingerprint {
  struct File {
    std::string name;    // relative to the scene file's folder (absolute when it lies elsewhere)
    std::string digest;  // common/digest.hpp, hex
  };
  std::filesystem::path scene;                    // the scene file as it was given
  std::vector<File> files;                        // the scene file first
  std::map<std::string, std::string> parameters;  // Scene::parameters (-D), where any
  std::string digest;                             // over the files' names and digests, in order, and the parameters

  bool operator==(const SceneFingerprint& other) const { return digest == other.digest; }
};

SceneFingerprint fingerprint(const Scene& scene);
// What differs from a recorded fingerprint (`from`, "then") to the current one (`to`, "now"), for a message:
// "the scene file differs", "meshes/a.obj differs", "textures/b.png is read now, not then", …; "" when the same.
std::string difference(const SceneFingerprint& from, const SceneFingerprint& to);

}  // namespace clr::scene
