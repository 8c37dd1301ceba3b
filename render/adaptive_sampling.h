// Adaptive sampling (render.adaptive): after a first pass over the image, where the rest of the
// samples go. docs/rendering.md#adaptive-sampling-renderadaptive gives the figures.
#pragma once

#include <cstdint>
#include <vector>

#include "aov.h"

namespace mf::render {

/// Sets end[p], the samples pixel p ends with, so that the image costs what `samples` per pixel
/// would have (cost: the rays a pixel's samples cast, from the first pass). The samples left go to
/// pixel p in proportion to w_p = sigma_p / (sqrt(L_p^2 + 0.01) sqrt(c_p)) (sigma: the spread
/// of one sample's luminance, c: one sample's rays), the allocation that minimises the summed
/// relative variance at that cost; w is the largest over the pixel and its 8 neighbours, so that
/// one lucky first pass does not starve an edge. Each pixel gets at most `cap`. Serial and in
/// pixel order, the rounding carried: the same on any thread count.
void allocateSamples(const std::vector<LuminanceMoments>& moments, const std::vector<uint64_t>& rays, int width, int height,
                     int samples, int cap, std::vector<int>& end);

}  // namespace mf::render
