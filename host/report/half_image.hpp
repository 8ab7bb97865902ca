#pragma once
// An image as the report page carries it: its RGB values as IEEE half floats (Imath's, as OpenEXR stores them),
// little-endian, in base64 text. Half floats keep the image HDR in the page (the exposure slider and the pixel
// readout need the values, not a tonemapped picture) at half the bytes of float32.
#include <string>
#include <string_view>

#include "image/image.hpp"

namespace clr::report {

// Base64 (RFC 4648, with padding) of `bytes`.
std::string base64(std::string_view bytes);
// The image's row-major RGB values as halves in base64. Values beyond the half range (±65504) are clamped to it,
// so that a bright pixel reads as bright rather than infinite; NaN stays NaN.
std::string half_base64(const image::Image& img);
// The image's red channel alone (a single-channel map kept in an Image), as half_base64 encodes it.
std::string half_base64_red(const image::Image& img);

}  // namespace clr::report
