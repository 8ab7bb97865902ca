#pragma once
// An image as the report page carries it: its RGB values as IEEE half floats (Imath's, as OpenEXR stores them),
// split into two byte planes (every value's high byte, then every low byte), zlib-compressed and in base64 text.
// Half floats keep the image HDR in the page (the exposure slider and the pixel readout need the values, not a
// tonemapped picture) at half the bytes of float32; the planes put the slowly varying sign/exponent bytes together,
// so that deflate takes a third to two fifths off even a noisy render (the page inflates them with the browser's
// DecompressionStream).
#include <string>
#include <string_view>

#include "image/image.hpp"

namespace clr::report {

// Base64 (RFC 4648, with padding) of `bytes`.
std::string base64(std::string_view bytes);
// The image's row-major RGB values packed so. Values beyond the half range (±65504) are clamped to it, so that a
// bright pixel reads as bright rather than infinite; NaN stays NaN.
std::string half_base64(const image::Image& img);
// The image's red channel alone (a single-channel map kept in an Image), as half_base64 encodes it.
std::string half_base64_red(const image::Image& img);

}  // namespace clr::report
