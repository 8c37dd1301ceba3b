#include "path_tracer.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>

#include "adaptive_sampling.h"
#include "integrator.h"

namespace mf::render {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

PathTracer::PathTracer(std::vector<Surface> surfaces, const RenderSettings& settings, double frameInterval)
    : impl_(std::make_unique<Integrator>(std::move(surfaces), settings, frameInterval)) {}

PathTracer::~PathTracer() = default;

size_t PathTracer::triangleCount() const {
  size_t n = 0;
  for (const auto& s : impl_->surfaces) n += s.mesh.size();
  return n;
}

std::vector<std::string> PathTracer::maskNames() const { return impl_->maskNames; }

void PathTracer::setNextFrame(const RenderSettings& next, double interval) {
  impl_->nextCamera = Camera(next);
  impl_->frameInterval = interval;
}

Image PathTracer::render(int frame, RenderStats* stats, const std::function<void(int, int)>& progress,
                         std::vector<RecordedRay>* record, Aovs* aovs) const {
  const Integrator& im = *impl_;
  const RenderSettings& s = im.settings;
  Image image(s.width, s.height);
  if (aovs) *aovs = Aovs(s.width, s.height, im.maskNames);
  const auto t0 = Clock::now();
  tbb::combinable<uint64_t> rays([] { return uint64_t(0); });
  tbb::combinable<std::vector<RecordedRay>> recorded;
  std::atomic<int> rowsDone{0};
  std::mutex progressMutex;
  // One row per task: pixels are independent, so the schedule cannot change any value.
  // Adaptive sampling: a first pass gives every pixel its share of the samples; the rest go
  // where that pass's relative noise is largest (see allocateSamples).
  const int width = s.width, height = s.height;
  const size_t pixels = size_t(width) * height;
  const bool adaptive = s.adaptive > 0 && s.samples >= 4;
  const int firstPass = adaptive ? std::max(2, int(std::lround(s.samples * (1 - s.adaptive)))) : s.samples;
  std::vector<LuminanceMoments> moments(pixels);
  std::vector<uint64_t> pixelRays(pixels, 0);
  std::optional<AovAccumulator> aovSums;
  if (aovs) aovSums.emplace(*aovs);
  std::vector<int> end(pixels, firstPass);  // each pass takes a pixel from its moments' count to here
  auto pass = [&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, height, 1), [&](const tbb::blocked_range<int>& rows) {
      RayLog log{0, record ? &recorded.local() : nullptr};
      Hit hit, shadow;
      hit.log = shadow.log = &log;  // the hits carry it, so the integrator's methods need not
      for (int y = rows.begin(); y < rows.end(); ++y) {
        for (int x = 0; x < width; ++x) {
          const size_t p = size_t(y) * width + x;
          // The frame is part of the pixel's seed only with animated_seed (see docs/rendering.md).
          const uint64_t seed = Sampler::pixelSeed(x, y, s.animatedSeed ? uint64_t(frame) + 1 : 0);
          const uint64_t raysBefore = log.rays;
          Vec3 sum;
          for (int k = int(moments[p].n), last = end[p]; k < last; ++k) {
            Sampler smp(seed, uint32_t(k), !s.sobol);
            Real jx, jy;
            smp.get2D(0, jx, jy);
            // The sample's moment in the shutter, shared by every ray of its path; a pair of its
            // own, so frames without blur keep their bits.
            if (im.blur) hit.time = shadow.time = float(smp.get1D(Sampler::kTimePair));
            const Vec3 d = im.camera.direction(x + jx, y + jy);
            PrimarySample first;
            Vec3 c = im.trace(s.cameraPosition, d, smp, hit, shadow, aovs ? &first : nullptr);
            if (!isFinite(c)) c = {};
            sum += c;
            moments[p].add(c);
            if (aovs) aovSums->add(p, first);
          }
          image.set(x, y, image.at(x, y) + sum);  // the pass's sum; the mean is taken at the end
          pixelRays[p] += log.rays - raysBefore;
        }
        const int done = ++rowsDone;
        if (progress) {
          std::lock_guard<std::mutex> lock(progressMutex);
          progress(done, adaptive ? 2 * height : height);
        }
      }
      rays.local() += log.rays;
    });
  };
  pass();
  if (adaptive) {
    allocateSamples(moments, pixelRays, width, height, s.samples, s.samples * 8, end);
    pass();
  }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const uint32_t n = moments[size_t(y) * width + x].n;
      image.set(x, y, n ? image.at(x, y) / Real(n) : Vec3());
    }
  if (aovs) aovSums->finish(moments);
  if (stats) {
    stats->rays = rays.combine(std::plus<uint64_t>());
    stats->seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  }
  if (record) recorded.combine_each([&](const std::vector<RecordedRay>& r) { record->insert(record->end(), r.begin(), r.end()); });
  return image;
}

double PathTracer::coverage(const std::function<bool(const Surface&)>& counts) const {
  const Integrator& im = *impl_;
  const RenderSettings& s = im.settings;
  std::vector<uint8_t> accept(im.surfaces.size());
  for (size_t g = 0; g < im.surfaces.size(); ++g) accept[g] = counts(im.surfaces[g]);
  const uint64_t covered = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, s.height), uint64_t(0),
      [&](const tbb::blocked_range<int>& rows, uint64_t n) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (int y = rows.begin(); y < rows.end(); ++y)
          for (int x = 0; x < s.width; ++x) {
            const Vec3 d = im.camera.direction(x + 0.5, y + 0.5);
            float tnear = 0;
            for (int bounce = 0; bounce < 64; ++bounce) {
              RTCRayHit rh = makeRay(float(s.cameraPosition.x), float(s.cameraPosition.y), float(s.cameraPosition.z),
                                     float(d.x), float(d.y), float(d.z), tnear, std::numeric_limits<float>::infinity());
              rtcIntersect1(im.geometry.scene(), &context, &rh);
              if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
              if (accept[rh.hit.geomID]) {
                ++n;
                break;
              }
              tnear = rh.ray.tfar * (1 + 1e-6f) + float(im.epsilon);
            }
          }
        return n;
      },
      std::plus<uint64_t>());
  return s.width > 0 && s.height > 0 ? double(covered) / (double(s.width) * s.height) : 0;
}

double PathTracer::traceBare(const std::vector<RecordedRay>& rays) const {
  const auto t0 = Clock::now();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = r.begin(); i < r.end(); ++i) {
      const RecordedRay& q = rays[i];
      RTCRayHit rh = makeRay(q.org[0], q.org[1], q.org[2], q.dir[0], q.dir[1], q.dir[2], q.tnear, q.tfar);
      rtcIntersect1(impl_->geometry.scene(), &context, &rh);
    }
  });
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::vector<Surface> solidSurfaces(const Scene& scene, const RenderSettings& settings) {
  std::vector<Surface> out;
  for (size_t i = 0; i < scene.solids.size(); ++i) {
    const MaterialSpec& m = settings.solidMaterials.at(i);
    if (!m.visible) continue;
    out.push_back({scene.solids[i].name.empty() ? "solid" : scene.solids[i].name, solidMesh(scene.solids[i], m.thickness), m, true});
  }
  for (const PropSpec& prop : settings.props)
    if (prop.material.visible) out.push_back({prop.shape.name, solidMesh(prop.shape, prop.material.thickness), prop.material, true});
  return out;
}

}  // namespace mf::render
