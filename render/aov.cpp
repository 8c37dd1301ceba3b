#include "aov.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mf::render {

Aovs::Aovs(int w, int h, std::vector<std::string> masks)
    : width(w), height(h), albedo(size_t(w) * h * 3, 0.0f), normal(size_t(w) * h * 3, 0.0f),
      depth(size_t(w) * h, std::numeric_limits<float>::infinity()), variance(size_t(w) * h, 0.0f),
      motion(size_t(w) * h * 2, 0.0f),
      maskNames(std::move(masks)), mask(size_t(w) * h * maskNames.size(), 0.0f) {}

namespace {
double luminance(const Vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
}  // namespace

void AovPixel::add(const PrimarySample& s, const Vec3& radiance) {
  ++n_;
  albedo_ += s.albedo;
  normal_ += s.normal;
  if (s.depth >= 0) depth_ += s.depth, ++hits_;
  if (s.mask >= 0 && size_t(s.mask) < mask_.size()) mask_[s.mask] += 1;
  if (s.moved) motion_[0] += s.motion[0], motion_[1] += s.motion[1], ++moved_;
  const double l = luminance(radiance);
  lum_ += l, lum2_ += l * l;
}

void AovPixel::store(Aovs& out, int x, int y) const {
  if (n_ == 0) return;
  const size_t p = size_t(y) * out.width + x;
  const Vec3 a = albedo_ / Real(n_);
  const Real len = std::sqrt(dot(normal_, normal_));
  const Vec3 nrm = len > 0 ? normal_ / len : Vec3{};
  for (int c = 0; c < 3; ++c) {
    out.albedo[3 * p + c] = float(a[c]);
    out.normal[3 * p + c] = float(nrm[c]);
  }
  // The mean over the samples that hit something: at a silhouette, the nearer surface's.
  out.depth[p] = hits_ ? float(depth_ / hits_) : std::numeric_limits<float>::infinity();
  // The variance of the mean: the samples' (unbiased) variance over their count.
  const double mean = lum_ / n_;
  out.variance[p] = n_ > 1 ? float(std::max(0.0, (lum2_ - n_ * mean * mean) / (n_ - 1)) / n_) : 0.0f;
  for (size_t m = 0; m < mask_.size(); ++m) out.mask[p * mask_.size() + m] = float(mask_[m] / n_);
  for (int c = 0; c < 2; ++c) out.motion[2 * p + c] = moved_ ? float(motion_[c] / moved_) : 0.0f;
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
