// surface_bench: the surfacing stage against OpenVDB's own route at the same voxel size
// (tools::ParticlesToLevelSet, spheres of one particle spacing, then LevelSetFilter
// mean-curvature smoothing), on the particles of a settled dam break (the Martin & Moyce tank
// with its water at rest: a layer 0.4 a deep, jittered lattice), the same with spray above it
// (a droplet of 1 to 8 particles per 100 particles of the layer, 4.5 % more particles, which
// surfacing keeps apart as separate bodies), and on the ball of the tests. Each measurement
// runs in its own process, so peak memory is that method's alone.
//
//   surface_bench [--particles 100000,1000000] [--curvature-iterations 4]
#include <fmt/format.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <random>
#include <thread>

#include "pipeline/scene_stages.h"
#include "surfacing/mesh_io.h"
#include "surfacing/particle_surface.h"
#include "bench_args.h"

using openvdb::Vec3d;

namespace {

struct ParticleList {
  using PosType = openvdb::Vec3R;
  const std::vector<Vec3d>& p;
  double radius;
  size_t size() const { return p.size(); }
  void getPos(size_t n, openvdb::Vec3R& xyz) const { xyz = p[n]; }
  void getPosRad(size_t n, openvdb::Vec3R& xyz, openvdb::Real& r) const {
    xyz = p[n];
    r = radius;
  }
};

std::vector<Vec3d> settledDamBreak(long target, double& spacing) {
  const double a = 0.05715, L = 5 * a, W = a, depth = 0.4 * a;  // same volume as the a x 2a x a column
  spacing = std::cbrt(L * W * depth / double(target));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.1 * spacing, 0.1 * spacing);
  std::vector<Vec3d> p;
  for (double z = 0.5 * spacing; z < W; z += spacing)
    for (double y = 0.5 * spacing; y < depth; y += spacing)
      for (double x = 0.5 * spacing; x < L; x += spacing) p.emplace_back(x + u(rng), y + u(rng), z + u(rng));
  return p;
}

// Droplets of 1 to 8 particles (a jittered 2x2x2 block, filled in order), one per 100
// particles of the layer, at random above it: from 2 spacings over the water to 0.5 a higher.
void addSpray(std::vector<Vec3d>& p, double spacing) {
  const double a = 0.05715, L = 5 * a, W = a, depth = 0.4 * a;
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> ux(0, L), uy(depth + 2 * spacing, depth + 0.5 * a), uz(0, W);
  std::uniform_real_distribution<double> jitter(-0.1 * spacing, 0.1 * spacing);
  std::uniform_int_distribution<int> count(1, 8);
  const size_t droplets = p.size() / 100;
  for (size_t d = 0; d < droplets; ++d) {
    const Vec3d c(ux(rng), uy(rng), uz(rng));
    const int n = count(rng);
    for (int i = 0; i < n; ++i)
      p.emplace_back(c.x() + (i & 1) * spacing + jitter(rng), c.y() + ((i >> 1) & 1) * spacing + jitter(rng),
                     c.z() + ((i >> 2) & 1) * spacing + jitter(rng));
  }
}

std::vector<Vec3d> ball(double& spacing) {
  spacing = 0.01;
  const Vec3d c(0.3, 0.3, 0.3);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.3 * spacing, 0.3 * spacing);
  std::vector<Vec3d> p;
  for (double z = 0.205; z < 0.4; z += spacing)
    for (double y = 0.205; y < 0.4; y += spacing)
      for (double x = 0.205; x < 0.4; x += spacing)
        if ((Vec3d(x, y, z) - c).length() <= 0.1) p.push_back(Vec3d(x, y, z) + Vec3d(u(rng), u(rng), u(rng)));
  return p;
}

double roughnessVoxels(const openvdb::FloatGrid& ls) {
  const auto mesh = mf::surfacing::levelSetToMesh(ls);
  double s = 0, s2 = 0;
  for (const auto& v : mesh.vertices) {
    const double r = (Vec3d(v) - Vec3d(0.3, 0.3, 0.3)).length();
    s += r;
    s2 += r * r;
  }
  const double n = double(mesh.vertices.size()), mean = s / n;
  return std::sqrt(std::max(0.0, s2 / n - mean * mean)) / ls.voxelSize()[0];
}

struct Result {
  double seconds = 0, voxels = 0, peakMiB = 0, roughness = -1;
};

// Runs f in a child process; returns its timing, voxel count and the child's peak memory.
template <class F>
Result isolated(F&& f) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe");
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    Result r = f();
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    r.peakMiB = u.ru_maxrss / 1024.0;
    if (write(fds[1], &r, sizeof r) != ssize_t(sizeof r)) _exit(1);
    _exit(0);
  }
  close(fds[1]);
  Result r;
  if (read(fds[0], &r, sizeof r) != ssize_t(sizeof r)) r.seconds = -1;
  close(fds[0]);
  waitpid(pid, nullptr, 0);
  return r;
}

using Clock = std::chrono::steady_clock;

Result ours(const std::vector<Vec3d>& p, double spacing, bool rough) {
  const mf::SceneStages scene = mf::loadSceneStages("dam_break");
  const auto t0 = Clock::now();
  const auto s = mf::surfacing::particlesToSurface(p, {}, spacing, scene.surfacing);
  Result r;
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  r.voxels = double(s.levelSet->activeVoxelCount());
  if (rough) r.roughness = roughnessVoxels(*s.levelSet);
  return r;
}

Result openvdbRoute(const std::vector<Vec3d>& p, double spacing, int iterations, bool rough) {
  const mf::SceneStages scene = mf::loadSceneStages("dam_break");
  const double voxel = scene.surfacing.voxelRatio * spacing;
  const auto t0 = Clock::now();
  auto ls = openvdb::createLevelSet<openvdb::FloatGrid>(voxel, 3.0);
  openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid> raster(*ls);
  raster.setRmin(0.5);
  raster.rasterizeSpheres(ParticleList{p, spacing});
  raster.finalize(true);
  openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*ls);
  for (int i = 0; i < iterations; ++i) filter.meanCurvature();
  Result r;
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  r.voxels = double(ls->activeVoxelCount());
  if (rough) r.roughness = roughnessVoxels(*ls);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<long> sizes = {100000, 1000000};
  int iterations = 4;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--particles") {
      sizes.clear();
      for (long n : mf::bench::wholeList(a, argv[i + 1])) sizes.push_back(n);
    } else if (a == "--curvature-iterations") {
      iterations = int(mf::bench::whole(a, argv[i + 1]));
    }
  }
  openvdb::initialize();
  fmt::print("surfacing vs OpenVDB's ParticlesToLevelSet + {} x LevelSetFilter::meanCurvature, same voxel size "
             "(0.5 spacings), {} hardware threads\n",
             iterations, std::thread::hardware_concurrency());
  fmt::print("{:>22} {:>9} | {:>9} {:>11} {:>9} {:>10} | {:>9} {:>11} {:>9} {:>10}\n", "case", "particles", "ours s",
             "voxels", "peak MiB", "rough vox", "vdb s", "voxels", "peak MiB", "rough vox");
  double spacing = 0;
  const auto b = ball(spacing);
  const Result ob = isolated([&] { return ours(b, spacing, true); });
  const Result vb = isolated([&] { return openvdbRoute(b, spacing, iterations, true); });
  fmt::print("{:>22} {:>9} | {:>9.3f} {:>11.0f} {:>9.0f} {:>10.3f} | {:>9.3f} {:>11.0f} {:>9.0f} {:>10.3f}\n", "ball (tests)",
             b.size(), ob.seconds, ob.voxels, ob.peakMiB, ob.roughness, vb.seconds, vb.voxels, vb.peakMiB, vb.roughness);
  for (long n : sizes) {
    auto p = settledDamBreak(n, spacing);
    for (const bool spray : {false, true}) {
      if (spray) addSpray(p, spacing);
      const Result o = isolated([&] { return ours(p, spacing, false); });
      const Result v = isolated([&] { return openvdbRoute(p, spacing, iterations, false); });
      fmt::print("{:>22} {:>9} | {:>9.3f} {:>11.0f} {:>9.0f} {:>10} | {:>9.3f} {:>11.0f} {:>9.0f} {:>10}\n",
                 spray ? "  + spray" : "settled dam break", p.size(), o.seconds, o.voxels, o.peakMiB, "", v.seconds,
                 v.voxels, v.peakMiB, "");
      std::fflush(stdout);
    }
  }
  return 0;
}
