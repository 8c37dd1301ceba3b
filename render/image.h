// Linear RGB images in memory, and the files the render stage writes: linear half-float EXR
// for compositing and sRGB PNG for viewing (OpenImageIO), each written under a temporary name
// and renamed. Also the frame-diff metric used by tests and `multifluid diff`.
#pragma once

#include <string>
#include <vector>

#include "sim/vec3.h"

namespace mf::render {

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // linear, row-major from the top, 3 floats per pixel

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(size_t(w) * h * 3, 0.0f) {}
  Vec3 at(int x, int y) const {
    const float* p = &rgb[(size_t(y) * width + x) * 3];
    return {p[0], p[1], p[2]};
  }
  void set(int x, int y, const Vec3& c) {
    float* p = &rgb[(size_t(y) * width + x) * 3];
    p[0] = float(c.x), p[1] = float(c.y), p[2] = float(c.z);
  }
};

/// Writes by extension: .exr (linear, half float) or .png (sRGB, 8 bit, clamped).
void writeImage(const std::string& path, const Image& image);
/// A multi-channel EXR (zip): channel c of pixel p is data[p * names.size() + c]; half floats
/// but for the channels whose `fullFloat` is set. Written under a temporary name and renamed.
void writeExrChannels(const std::string& path, int width, int height, const std::vector<std::string>& names,
                      const std::vector<float>& data, const std::vector<bool>& fullFloat);
/// Reads any format OpenImageIO knows as linear RGB (PNG is converted from sRGB). Of a
/// multi-layer EXR, the channels named R, G and B (the beauty).
Image readImage(const std::string& path);

/// Per-pixel comparison in the manner of OpenImageIO's idiff (as Cycles' render tests use it):
/// a pixel fails when any channel differs by more than `failThreshold`; the images differ
/// when more than `failPercent` % of pixels fail. Values are compared as displayed (sRGB,
/// clamped to [0, 1]), so that a threshold means the same on EXR and PNG.
struct ImageDiff {
  bool sizeMismatch = false;
  double meanError = 0, maxError = 0, rmsError = 0;
  size_t failedPixels = 0, pixels = 0;
  double failedPercent() const { return pixels ? 100.0 * failedPixels / pixels : 0; }
  bool passes(double failPercent) const { return !sizeMismatch && failedPercent() <= failPercent; }
};
ImageDiff compareImages(const Image& a, const Image& b, double failThreshold, Image* difference = nullptr);

float linearToSrgb(float v);
float srgbToLinear(float v);

}  // namespace mf::render
