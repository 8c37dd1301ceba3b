// The integrator: paths through nested dielectrics with priorities (Schmidt & Budge 2002),
// Fresnel reflection and refraction, Beer-Lambert absorption, scattering and emissive media,
// diffuse surfaces and the table, lit by the spherical lamp and the sky, with next-event
// estimation, MIS, path regularisation and Russian roulette (docs/rendering.md). It answers one
// camera ray at a time; the image loop around it is PathTracer::render (path_tracer.cpp).
// Internal to the render stage: it holds Embree's scene (RayScene).
#pragma once
#include <string>
#include <vector>

#include "aov.h"
#include "camera.h"
#include "geometry.h"
#include "lights.h"
#include "media.h"
#include "ramp_media.h"
#include "ray_scene.h"
#include "sampler.h"
#include "settings.h"
#include "warp.h"

namespace mf::render {

struct Integrator {
  RenderSettings settings;
  std::vector<Surface> surfaces;
  std::vector<MaterialSpec> materials;  // one per surface (geometry id)
  RayScene geometry;
  Real epsilon;  // ray offset, m (the geometry's)
  Camera camera;
  Camera nextCamera;           // the next frame's (motion vectors)
  Real frameInterval = 0;      // s to the next frame; 0: no motion vectors
  bool blur;                   // surfaces move over the shutter (render.shutter)
  SphereLight light;
  Sky sky;
  std::vector<std::string> maskNames;  // the fluids' names (AOV masks)
  std::vector<int> maskOf;             // per geometry: its index in maskNames, -1 for solids
  RampMedia ramps;  // the media whose coefficients come from attribute grids
  // The camera ray cone's spread, radians: a pixel's angle at the image centre over sqrt(samples),
  // the share of the pixel one sample stands for (as pbrt scales its ray differentials), so that
  // the filtered texture converges to the point-sampled one as the samples grow.
  Real pixelSpread;

  /// `frameInterval`: the frame's duration, s, for motion blur (render.shutter of it; 0: none).
  Integrator(std::vector<Surface> surfaces, const RenderSettings& s, double frameInterval);

  /// The radiance along the camera ray o + t d. `h`, `shadow`: scratch hits (the caller's, so
  /// that they are not cleared for every path; they carry the ray log). `first`: where to record
  /// the primary hit and the specular chain's albedo and fluid (AOVs); recording draws no
  /// samples, so the path is the same with or without.
  Vec3 trace(Vec3 o, Vec3 d, Sampler& smp, Hit& h, Hit& shadow, PrimarySample* first = nullptr) const;

  // The parts of a path (integrator.cpp says what each does).
  MF_INLINE void intersect(const Vec3& o, const Vec3& d, Real tfar, int leaving, unsigned leavingPrim, Hit& hit,
                           bool shading = true, const Real* knownLight = nullptr) const;
  MF_INLINE void goOnPast(const Hit& h, const Vec3& d, bool group, Vec3& o, int& leaving, unsigned& leavingPrim) const;
  MF_INLINE int crossCoincident(const Hit& h, const Vec3& d, MediumStack& after) const;
  Vec3 transmittance(Vec3 o, const Vec3& d, Real dist, int leaving, unsigned leavingPrim, MediumStack stack, Hit& h,
                     bool& crossed) const;
  Vec3 directLight(const Vec3& p, const Vec3* normal, int leaving, unsigned leavingPrim, const MediumStack& stack,
                   Real u1, Real u2, Hit& scratch, const Vec3* cone = nullptr, Real coneCos = 1) const;
  void recordMotion(const Hit& h, PrimarySample& first) const;
  void recordHit(const Hit& h, const Vec3& d, bool& primary, PrimarySample& first) const;
  Vec3 diffuseBounce(const Hit& h, const Vec3& albedo, Vec3& o, Vec3& d, const MediumStack& stack, Sampler& smp,
                     Hit& scratch) const;
  MF_INLINE static bool russianRoulette(Vec3& throughput, Sampler& smp);
};

}  // namespace mf::render
