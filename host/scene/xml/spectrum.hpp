#pragma once
// Spectra given as wavelength:value pairs, reduced to linear sRGB as Mitsuba 3's RGB variants do: the piecewise
// linear spectrum (zero outside its wavelengths) is integrated against the CIE 1931 2° colour-matching functions
// over 360–830 nm, normalised so that a flat spectrum of 1 has luminance Y = 1, and converted XYZ → linear sRGB.
// Reflectances are clamped to [0, 1], emission and unbounded quantities (eta, k, IORs) to ≥ 0. Everything but
// emission is integrated under CIE illuminant D65 (normalised to ȳ·D65 instead), as Mitsuba 3 does to match its
// spectral modes, where a reflectance is seen under the D65 white of sRGB: a flat reflectance is then grey.
#include <vector>

#include "scene/frame.hpp"

namespace clr::scene {

// The wavelengths (nm) the colour-matching functions span: a flat spectrum is flat between these.
inline constexpr float kCieFirst = 360.0f, kCieLast = 830.0f;

// CIE 1931 2° colour-matching functions x̄, ȳ, z̄ at wavelength λ (nm): the CIE's table every 5 nm, linear between
// (zero outside 360–830 nm).
Vec3 cie1931_xyz(float lambda);
Vec3 xyz_to_linear_srgb(const Vec3& xyz);

// CIE standard illuminant D65's relative power at λ (nm; 100 at 560 nm), linear between its 10 nm table entries.
float cie_d65(float lambda);

// `wavelengths` strictly increasing, same size as `values` (at least 2); `d65`: under illuminant D65 (everything
// but emission).
Rgb spectrum_to_rgb(const std::vector<float>& wavelengths, const std::vector<float>& values, bool bounded, bool d65);

}  // namespace clr::scene
