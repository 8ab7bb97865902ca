#pragma once
// Spectra given as wavelength:value pairs, reduced to linear sRGB as Mitsuba 3's RGB variants do: the piecewise
// linear spectrum (zero outside its wavelengths) is integrated against the CIE 1931 2° colour-matching functions
// over 360–830 nm, normalised so that a flat spectrum of 1 has luminance Y = 1, and converted XYZ → linear sRGB.
// Reflectances are clamped to [0, 1], emission and unbounded quantities (eta, k, IORs) to ≥ 0.
#include <vector>

#include "scene/frame.hpp"

namespace clr::scene {

// CIE 1931 2° colour-matching functions x̄, ȳ, z̄ at wavelength λ (nm), by the multi-lobe Gaussian fit of Wyman,
// Sloan and Shirley (JCGT 2013), within about 1 % of the tabulated functions' peak values.
Vec3 cie1931_xyz(float lambda);
Vec3 xyz_to_linear_srgb(const Vec3& xyz);

// `wavelengths` strictly increasing, same size as `values` (at least 2).
Rgb spectrum_to_rgb(const std::vector<float>& wavelengths, const std::vector<float>& values, bool bounded);

}  // namespace clr::scene
