#pragma once
// What a `clradiosity reference` image records of its render in its EXR header, and the check of any reference
// image against the scene and view it is to be compared with (train --reference, render --reference, sweep
// --reference): an image path-traced from another scene or another sensor is refused, not measured against.
#include <cstdint>
#include <map>
#include <string>

#include "scene/camera.hpp"

namespace clr::scene {

// The header entries that decide a reference's samples beside their count: `reference --resume` continues an image
// only under the same values.
std::map<std::string, std::string> reference_record(const std::string& scene_digest, const Camera& camera, int sensor,
                                                    int max_depth, std::uint64_t seed);

// InputError ("OPTION FILE: …") when the header `attributes` names another scene (its digest) or another sensor
// than `sensor` (< 0: a view of no sensor, not judged). Images that record neither (Tungsten's, another renderer's)
// pass: only what is recorded is judged. Returns a warning, or "", where the image holds less than the whole transport
// (a max depth), which the model learns whole.
std::string check_reference_record(const std::map<std::string, std::string>& attributes,
                                   const std::string& scene_digest, int sensor, const std::string& option,
                                   const std::string& file);

}  // namespace clr::scene
