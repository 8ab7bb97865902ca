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

  // The whole record: a digest alone would let a record whose file list was edited (or whose digest was copied from
  // another run) pass. The scene file's own name is left out (a renamed scene is the same scene).
  bool operator==(const SceneFingerprint& other) const {
    if (digest != other.digest || parameters != other.parameters || files.size() != other.files.size()) return false;
    for (std::size_t i = 0; i < files.size(); ++i)
      if (files[i].digest != other.files[i].digest || (i > 0 && files[i].name != other.files[i].name)) return false;
    return true;
  }
};

// The digest over the files' names and digests and the -D parameters (SceneFingerprint::digest), so that a record can
// be checked against its own file list.
std::string files_digest(const std::vector<SceneFingerprint::File>& files,
                         const std::map<std::string, std::string>& parameters = {});

SceneFingerprint fingerprint(const Scene& scene);
// What differs from a recorded fingerprint (`from`, "then") to the current one (`to`, "now"), for a message:
// "the scene file differs", "meshes/a.obj differs", "textures/b.png is read now, not then", …; "" when the same.
std::string difference(const SceneFingerprint& from, const SceneFingerprint& to);

}  // namespace clr::scene
