// A feature-guided denoiser for the path tracer's frames: the edge-avoiding à-trous wavelet
// filter of Dammertz et al. 2010 ("Edge-avoiding À-Trous wavelet transform for fast global
// illumination filtering", HPG), with the per-pixel variance guidance and edge-stopping functions
// of SVGF (Schied et al. 2017, "Spatiotemporal variance-guided filtering", HPG; spatial part only).
//
// The noisy image is divided by the albedo AOV (demodulated) so that the filter smooths light,
// not texture, and multiplied by the same pixel's albedo again after. Each of `iterations` passes is a 5x5 B3-spline
// kernel with holes (taps 2^i pixels apart); a tap's weight falls with the difference in normal,
// in depth (against the depth's own screen-space gradient), in albedo, and in luminance (against
// the standard deviation of the pixel's estimate, so that noise is smoothed and features are not).
//
// Deterministic: every output pixel is a fixed-order sum over its own taps, computed by one task;
// rows are split among threads, so the bits do not depend on the thread count.
#pragma once

#include "aov.h"
#include "image.h"

namespace mf::render {

struct DenoiseSettings {
  int iterations = 5;         // à-trous passes: the kernel spans 4 (2^iterations - 1) + 1 pixels
  float sigmaLuminance = 2;   // luminance differences in standard deviations (SVGF uses 4; see docs/rendering.md)
  float normalPower = 128;    // SVGF's sigma_n: weight max(0, n_p . n_q)^power
  float sigmaDepth = 1;       // SVGF's sigma_z: depth differences against the gradient's prediction
  float sigmaAlbedo = 0.25f;  // albedo differences (RGB distance) beyond which taps fade
};

/// The denoised image of `noisy` guided by `aovs` (the same size; render/aov.h). A pixel whose
/// features match no neighbour's is left as it is.
Image denoise(const Image& noisy, const Aovs& aovs, const DenoiseSettings& settings = {});

}  // namespace mf::render
