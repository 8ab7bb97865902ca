#pragma once
// The mean over an image's pixels and channels: how the training tests tell a model's overall brightness from the
// path tracer's (a run that ran away is bright everywhere).
#include "image/image.hpp"

namespace clr::test {

inline double image_mean(const image::Image& img) {
  double s = 0;
  for (float v : img.rgb) s += v;
  return s / double(img.rgb.size());
}

}  // namespace clr::test
