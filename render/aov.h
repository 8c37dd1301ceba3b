// Arbitrary output variables of the path tracer's primary hits, for the denoiser
// (render/denoise.h) and for compositing: per pixel, averaged over its samples.
//   albedo  the colour the pixel's light was reflected by: the first diffuse surface or
//           scattering medium along the camera path's specular chain (glass and clear liquid are
//           followed through, as Open Image Denoise asks of its albedo input); 1 where the chain
//           ends on the sky, the lamp or an emitter. The denoiser divides it out.
//   normal  the primary hit's shading normal, facing the camera, unit length (0 on the sky)
//   depth   the primary hit's distance from the camera, m (+inf where every sample saw the sky)
//   mask    per fluid: the fraction of samples whose specular chain met that fluid's surface
//           before any diffuse or scattering vertex (through glass walls, in reflections)
//   variance the variance of the pixel's mean luminance, from its samples (SVGF's guide)
//   albedoVariance the variance of the pixel's mean albedo (RGB summed): whether its samples
//           agree on the albedo (a texture they resolve) or scatter (a glass wall's reflect-or-
//           refract choice); the denoiser trusts the pixel's own albedo in the first case only
//   motion  forward motion vectors: where, in pixels from here (+x right, +y down), the primary
//           hit's point is in the next frame, by the surface's velocity and the camera's move;
//           the mean over the samples that hit something (0 on the sky)
// Written with the beauty as one multi-layer EXR (writeFrameExr).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "image.h"

namespace mf::render {

struct Aovs {
  int width = 0, height = 0;
  std::vector<float> albedo, normal;  // 3 per pixel
  std::vector<float> depth, variance;  // 1 per pixel
  std::vector<float> albedoVariance;   // 1 per pixel
  std::vector<float> motion;           // 2 per pixel: forward motion vector, pixels
  std::vector<std::string> maskNames;  // one per fluid
  std::vector<float> mask;             // maskNames.size() per pixel

  Aovs() = default;
  Aovs(int w, int h, std::vector<std::string> masks);
  size_t pixels() const { return size_t(width) * height; }
};

/// What one camera sample recorded at its primary hit and along its specular chain.
struct PrimarySample {
  Vec3 albedo{1, 1, 1};
  Vec3 normal;         // 0: the sky
  double depth = -1;   // < 0: the sky
  int mask = -1;       // index into Aovs::maskNames, -1: no fluid met
  bool moved = false;  // motion holds the primary hit's image motion to the next frame
  double motion[2] = {0, 0};  // pixels
};

/// A pixel's luminance over its samples, summed in order: the variance of its mean (the AOV
/// `variance`) and the noise that adaptive sampling allocates by.
struct LuminanceMoments {
  double sum = 0, sum2 = 0;
  uint32_t n = 0;
  void add(const Vec3& radiance);
  /// The samples' (unbiased) variance over their count; 0 below two samples.
  double varianceOfMean() const;
};

/// Sums every pixel's primary samples in place, in the Aovs' own buffers (a pixel's samples in
/// order, over any number of passes: the same bits on any thread count), then turns the sums
/// into the means.
class AovAccumulator {
 public:
  explicit AovAccumulator(Aovs& out);
  void add(size_t pixel, const PrimarySample& s);
  /// The means over each pixel's moments[p].n samples, and the variance from its moments.
  void finish(const std::vector<LuminanceMoments>& moments);

 private:
  Aovs& out_;
  std::vector<uint32_t> hits_, moved_;
  std::vector<double> albedoSquares_;  // per pixel, the sum over samples of |albedo|^2
};

/// The frame as one EXR: R,G,B (the image shipped: denoised where `noisy` is given),
/// beauty_noisy.R/G/B (the path tracer's own, when given), albedo.R/G/B, N.X/Y/Z, Z (float) and
/// mask.<fluid>; half floats otherwise, zip. Written under a temporary name and renamed.
void writeFrameExr(const std::string& path, const Image& beauty, const Image* noisy, const Aovs& aovs);

}  // namespace mf::render
