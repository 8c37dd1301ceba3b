// A path tracer for liquids in glass: nested dielectrics with priorities (Schmidt & Budge 2002,
// as production renderers resolve overlapping volumes), Fresnel reflection and refraction,
// Beer-Lambert absorption, a homogeneous scattering medium for wax, diffuse table and walls,
// a spherical area light sampled directly and a sky. Embree 3 finds the hits; TBB runs rows.
// This is the image loop around the integrator (integrator.h); the camera, sampler, lights,
// media and the ray scene are their own units beside them (docs/rendering.md).
//
// Deterministic: each pixel sample's values are Owen-scrambled Sobol points keyed by (pixel,
// sample, dimension) (render/sampler.h; the frame too with render.animated_seed), and pixels are
// independent, so the image bits do not depend on the thread count.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "aov.h"
#include "geometry.h"
#include "image.h"
#include "settings.h"

namespace mf::render {

struct Integrator;

struct RenderStats {
  uint64_t rays = 0;          // every ray cast into the scene (camera, bounce, shadow)
  double seconds = 0;         // wall time of the image
  double raysPerSecond() const { return seconds > 0 ? rays / seconds : 0; }
};

class PathTracer {
 public:
  /// `frameInterval`: the frame's duration, s, for motion blur (render.shutter of it; 0: none).
  PathTracer(std::vector<Surface> surfaces, const RenderSettings& settings, double frameInterval = 0);
  ~PathTracer();
  PathTracer(const PathTracer&) = delete;
  PathTracer& operator=(const PathTracer&) = delete;

  /// Renders the image. `progress(done, total)` is called now and then with completed rows
  /// (from any thread, serialised). `record`: keep every ray cast (for benchmarks). `aovs`: also
  /// the primary hits' buffers (render/aov.h; the image's bits are the same with or without).
  Image render(int frame, RenderStats* stats = nullptr,
               const std::function<void(int, int)>& progress = {},
               std::vector<RecordedRay>* record = nullptr, Aovs* aovs = nullptr) const;

  /// For the AOVs' motion vectors: the next frame's settings (its camera) and the time to it, s.
  /// Without it the motion vectors are 0.
  void setNextFrame(const RenderSettings& next, double interval);

  /// The fluids' names, one per mask channel of the AOVs: the surfaces that are not solids.
  std::vector<std::string> maskNames() const;

  /// The fraction of pixels whose centre ray, followed straight through every surface that
  /// `counts` rejects (glass walls), meets one it accepts: what a frame shows of the fluid.
  double coverage(const std::function<bool(const Surface&)>& counts) const;

  /// Casts `rays` with plain rtcIntersect1 and nothing else; returns wall seconds.
  double traceBare(const std::vector<RecordedRay>& rays) const;

  size_t triangleCount() const;

 private:
  std::unique_ptr<Integrator> impl_;
};

/// The scene's solids as glass (or what their material says) and the render stage's props,
/// ready for PathTracer.
std::vector<Surface> solidSurfaces(const Scene& scene, const RenderSettings& settings);

}  // namespace mf::render
