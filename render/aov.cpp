#include "aov.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mf::render {

Aovs::Aovs(int w, int h, std::vector<std::string> masks)
    : width(w), height(h), albedo(size_t(w) * h * 3, 0.0f), normal(size_t(w) * h * 3, 0.0f),
      depth(size_t(w) * h, std::numeric_limits<float>::infinity()), variance(size_t(w) * h, 0.0f),
      albedoVariance(size_t(w) * h, 0.0f),
      motion(size_t(w) * h * 2, 0.0f),
      maskNames(std::move(masks)), mask(size_t(w) * h * maskNames.size(), 0.0f) {}

void LuminanceMoments::add(const Vec3& c) {
  const double l = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
  sum += l, sum2 += l * l, ++n;
}

double LuminanceMoments::varianceOfMean() const {
  if (n < 2) return 0;
  const double mean = sum / n;
  return std::max(0.0, (sum2 - n * mean * mean) / (n - 1)) / n;
}

AovAccumulator::AovAccumulator(Aovs& out)
    : out_(out), hits_(out.pixels(), 0), moved_(out.pixels(), 0), albedoSquares_(out.pixels(), 0.0) {
  std::fill(out.depth.begin(), out.depth.end(), 0.0f);
}

void AovAccumulator::add(size_t p, const PrimarySample& s) {
  albedoSquares_[p] += lengthSquared(s.albedo);
  for (int c = 0; c < 3; ++c) {
    out_.albedo[3 * p + c] += float(s.albedo[c]);
    out_.normal[3 * p + c] += float(s.normal[c]);
  }
  if (s.depth >= 0) out_.depth[p] += float(s.depth), ++hits_[p];
  const size_t masks = out_.maskNames.size();
  if (s.mask >= 0 && size_t(s.mask) < masks) out_.mask[p * masks + s.mask] += 1;
  if (s.moved) out_.motion[2 * p] += float(s.motion[0]), out_.motion[2 * p + 1] += float(s.motion[1]), ++moved_[p];
}

void AovAccumulator::finish(const std::vector<LuminanceMoments>& moments) {
  const size_t masks = out_.maskNames.size();
  for (size_t p = 0; p < out_.pixels(); ++p) {
    const uint32_t n = moments[p].n;
    if (n == 0) {
      out_.depth[p] = std::numeric_limits<float>::infinity();
      continue;
    }
    float* a = &out_.albedo[3 * p];
    float* nrm = &out_.normal[3 * p];
    const double len = std::sqrt(double(nrm[0]) * nrm[0] + double(nrm[1]) * nrm[1] + double(nrm[2]) * nrm[2]);
    double mean2 = 0;
    for (int c = 0; c < 3; ++c) {
      mean2 += (double(a[c]) / n) * (double(a[c]) / n);
      a[c] = float(a[c] / double(n));
      nrm[c] = len > 0 ? float(nrm[c] / len) : 0.0f;
    }
    // How far the samples' albedos scatter (a glass wall's reflect-or-refract choice) against how
    // well they agree (a texture they resolve): the denoiser trusts the mean only in the second case.
    out_.albedoVariance[p] = n > 1 ? float(std::max(0.0, albedoSquares_[p] - n * mean2) / (double(n - 1) * n)) : 0.0f;
    // The mean over the samples that hit something: at a silhouette, the nearer surface's.
    out_.depth[p] = hits_[p] ? float(out_.depth[p] / double(hits_[p])) : std::numeric_limits<float>::infinity();
    out_.variance[p] = float(moments[p].varianceOfMean());
    for (size_t m = 0; m < masks; ++m) out_.mask[p * masks + m] = float(out_.mask[p * masks + m] / double(n));
    for (int c = 0; c < 2; ++c) out_.motion[2 * p + c] = moved_[p] ? float(out_.motion[2 * p + c] / double(moved_[p])) : 0.0f;
  }
}

void writeFrameExr(const std::string& path, const Image& beauty, const Image* noisy, const Aovs& aovs) {
  std::vector<std::string> names = {"R", "G", "B"};
  if (noisy) names.insert(names.end(), {"beauty_noisy.R", "beauty_noisy.G", "beauty_noisy.B"});
  names.insert(names.end(), {"albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z", "Z", "motion.X", "motion.Y"});
  for (const std::string& m : aovs.maskNames) names.push_back("mask." + m);
  std::vector<bool> fullFloat(names.size(), false);
  for (size_t c = 0; c < names.size(); ++c) fullFloat[c] = names[c] == "Z";  // depth needs more than half's 11 bits
  const size_t n = aovs.pixels(), k = names.size(), masks = aovs.maskNames.size();
  std::vector<float> data(n * k);
  for (size_t p = 0; p < n; ++p) {
    float* o = &data[p * k];
    for (int c = 0; c < 3; ++c) *o++ = beauty.rgb[3 * p + c];
    if (noisy)
      for (int c = 0; c < 3; ++c) *o++ = noisy->rgb[3 * p + c];
    for (int c = 0; c < 3; ++c) *o++ = aovs.albedo[3 * p + c];
    for (int c = 0; c < 3; ++c) *o++ = aovs.normal[3 * p + c];
    *o++ = aovs.depth[p];
    for (int c = 0; c < 2; ++c) *o++ = aovs.motion[2 * p + c];
    for (size_t m = 0; m < masks; ++m) *o++ = aovs.mask[p * masks + m];
  }
  writeExrChannels(path, aovs.width, aovs.height, names, data, fullFloat);
}

}  // namespace mf::render
