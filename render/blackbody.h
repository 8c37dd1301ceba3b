// The colour of a blackbody: Planck's spectral radiance integrated against the CIE 1931 2°
// colour matching functions (the multi-lobe Gaussian fit of Wyman, Sloan & Shirley 2013,
// JCGT 2(2)) from 360 to 830 nm, in linear sRGB (D65 white, Rec. 709 primaries). Used for
// flames: emission_ramp = { attribute = "temperature", blackbody = ... } (render/settings_file.cpp).
#pragma once

#include <algorithm>
#include <cmath>

#include "sim/vec3.h"

namespace mf {

/// CIE XYZ of a blackbody at `kelvin`, W / (m^2 sr) (Y in radiometric units weighted by y-bar;
/// only ratios matter here).
inline Vec3 blackbodyXyz(Real kelvin) {
  const auto lobe = [](Real l, Real mu, Real s1, Real s2) {
    const Real t = (l - mu) / (l < mu ? s1 : s2);
    return std::exp(-0.5 * t * t);
  };
  constexpr Real h = 6.62607015e-34, c = 2.99792458e8, k = 1.380649e-23;
  Vec3 xyz;
  constexpr Real step = 1;  // nm
  for (Real l = 360; l <= 830; l += step) {
    const Real x = 1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7) - 0.065 * lobe(l, 501.1, 20.4, 26.2);
    const Real y = 0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1);
    const Real z = 1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8);
    const Real m = l * 1e-9;
    const Real planck = 2 * h * c * c / (m * m * m * m * m) / std::expm1(h * c / (m * k * kelvin)) * (step * 1e-9);
    xyz += Vec3(x, y, z) * planck;
  }
  return xyz;
}

/// Linear sRGB of XYZ; out-of-gamut (negative) components clipped to 0.
inline Vec3 xyzToLinearSrgb(const Vec3& v) {
  return {std::max(Real(0), 3.2406 * v.x - 1.5372 * v.y - 0.4986 * v.z),
          std::max(Real(0), -0.9689 * v.x + 1.8758 * v.y + 0.0415 * v.z),
          std::max(Real(0), 0.0557 * v.x - 0.2040 * v.y + 1.0570 * v.z)};
}

}  // namespace mf
