// Rays per second of the full renderer against Embree's bare rtcIntersect1 on exactly the same
// rays (recorded during a second, identical render), in one run on one machine.
//   ./build/bench/render_bench [WIDTH HEIGHT SAMPLES]
// Target (issue 6): the full shading path at least 50 % of bare traversal. The ratio is also
// given in CPU time (all threads), which another job on the machine disturbs less than wall time.
#include <fmt/format.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <tbb/info.h>

#include <ctime>

#include "render/path_tracer.h"
#include "pipeline/scene_stages.h"
#include "bench_args.h"

using namespace mf;

static double cpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char** argv) {
  openvdb::initialize();
  const int width = argc > 3 ? int(bench::whole("WIDTH", argv[1])) : 480, height = argc > 3 ? int(bench::whole("HEIGHT", argv[2])) : 270;
  const int samples = argc > 3 ? int(bench::whole("SAMPLES", argv[3])) : 16;
  // The water-in-glass scene of the golden test, at benchmark size: a level-set ball of water
  // (voxel 1 mm) in a thick open glass on a checkered table, lit by a sphere light and the sky.
  const std::string text = fmt::format(R"(
[scene]
name = "bench"
end_time = 1
frame_rate = 1
domain_min = [-0.2, -0.1, -0.2]
domain_max = [0.2, 0.4, 0.2]
[solver]
particle_spacing = 0.01
[[phase]]
name = "water"
rest_density = 1000.0
[[solid]]
name = "glass"
shape = "cylinder"
base = [0.0, 0.0, 0.0]
radius = 0.06
height = 0.16
open_top = true
[[fluid]]
phase = "water"
min = [-0.02, 0.0, -0.02]
max = [0.02, 0.04, 0.02]
[effects.gravity]
[render]
width = {}
height = {}
samples = {}
camera_position = [0.0, 0.12, 0.45]
look_at = [0.0, 0.06, 0.0]
fov = 35
light_position = [0.3, 0.6, 0.4]
light_radius = 0.08
checker_size = 0.03
)",
                                       width, height, samples);
  const SceneStages sc = parseSceneStages(text, "bench");
  auto ball = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(0.045f, openvdb::Vec3f(0, 0.05f, 0), 0.001f, 3.0f);
  std::vector<render::Surface> surfaces;
  surfaces.push_back({"water", render::levelSetMesh(*ball), sc.render.phaseMaterials[0]});
  for (auto& s : render::solidSurfaces(sc.scene, sc.render)) surfaces.push_back(std::move(s));
  render::PathTracer tracer(std::move(surfaces), sc.render);

  render::RenderStats full;
  const double c0 = cpuSeconds();
  tracer.render(0, &full);
  const double fullCpu = cpuSeconds() - c0;
  std::vector<render::RecordedRay> rays;
  tracer.render(0, nullptr, {}, &rays);
  const double c1 = cpuSeconds();
  const double bareSeconds = tracer.traceBare(rays);
  const double bareCpu = cpuSeconds() - c1;
  const double bare = rays.size() / bareSeconds;
  fmt::print("render_bench: {}x{} x {} spp, {} triangles, {} threads\n", width, height, samples, tracer.triangleCount(),
             tbb::info::default_concurrency());
  fmt::print("  full renderer      {:>10} rays in {:.3f} s = {:>7.2f} Mrays/s\n", full.rays, full.seconds, full.raysPerSecond() / 1e6);
  fmt::print("  bare rtcIntersect1 {:>10} rays in {:.3f} s = {:>7.2f} Mrays/s\n", rays.size(), bareSeconds, bare / 1e6);
  fmt::print("  full / bare = {:.1f} %  (target >= 50 %)\n", 100 * full.raysPerSecond() / bare);
  fmt::print("  in CPU time: full {:.3f} s, bare {:.3f} s, full / bare = {:.1f} %\n", fullCpu, bareCpu, 100 * bareCpu / fullCpu);
  return 0;
}
