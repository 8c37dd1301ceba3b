// cycles_bench: our path tracer against Blender Cycles (Debian's blender, 3.4, background mode) on
// the same frames of shipped scenes, at equal wall time (issue 22).
//
//   cycles_bench [--multifluid PATH] [--frames dam_break:9,pour_glass:30,lava_lamp:70]
//                [--resolution 240x135] [--reference 1024] [--ours 4,8,16,32,64] [--cycles 2,4,8,16,32,64,128]
//                [--work DIR]
//
// For each scene:frame, `multifluid run` simulates and surfaces frames 0..F (with PLY meshes), and
// `multifluid export blender --meshes ply` writes the .blend: the same meshes, camera, light, sky,
// table and materials, which Cycles renders. Each renderer renders the frame at the spp ladder and
// at the reference spp; the error of each render is its rel RMSE against that renderer's own
// reference (noise, not the two renderers' different looks),
//   rel RMSE = sqrt(mean over pixels and channels of (x - r)^2 / (r^2 + 0.01))   (linear EXR)
// as render_noise_bench measures it. Times are each renderer's own per-frame render time (ours
// from the render stage's summary, Cycles' from its "Finished" line), both with mesh loading and
// BVH building and without process start-up. Cycles renders without a denoiser; ours is measured
// raw and denoised (render.denoise, its default). For each of our renders it prints Cycles' rel
// RMSE in the same time and the time Cycles needs for the same rel RMSE, both interpolated in
// log-log between its ladder's renders (never extrapolated), with their ratios to ours. The two
// references' rel RMSE against each other is printed too: how alike the two pictures are.
//
// Needs blender on PATH (scripts/setup.sh --with-blender). Run from the repository root.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "bench/rel_rmse.h"
#include "pipeline/process.h"
#include "render/image.h"
#include "bench_args.h"

namespace fs = std::filesystem;
using mf::pipeline::runProgram;
using mf::pipeline::SpawnOptions;
using mf::bench::relRmse;

namespace {

struct Options {
  std::string multifluid = "./build/pipeline/multifluid";
  std::vector<std::pair<std::string, int>> frames = {{"dam_break", 9}, {"pour_glass", 30}, {"lava_lamp", 70}};
  int width = 240, height = 135, reference = 1024;
  std::vector<int> ours = {4, 8, 16, 32, 64}, cycles = {2, 4, 8, 16, 32, 64, 128};
  std::string work;
};

std::vector<int> numbers(const std::string& flag, const std::string& s) {
  std::vector<int> v;
  for (long n : mf::bench::wholeList(flag, s)) v.push_back(int(n));
  return v;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

void run(const std::vector<std::string>& argv, const std::string& log) {
  SpawnOptions o;
  o.stdoutFile = log + ".out";
  o.stderrFile = log + ".err";
  o.timeoutSeconds = 7200;
  if (runProgram(argv, o) != 0)
    throw std::runtime_error(fmt::format("{} failed; see {}.err:\n{}", argv[0], log, slurp(log + ".err").substr(0, 2000)));
}

struct Render {
  int spp = 0;
  double seconds = 0;
  std::string exr;
};

/// Ours: the render stage of the run folder for one frame; the frame and its record are moved
/// away after each render, so that the next one renders again.
Render renderOurs(const Options& o, const fs::path& runDir, const std::string& scene, int frame, int spp, bool denoise) {
  const std::string tag = fmt::format("ours_{}{}", spp, denoise ? "_denoised" : "");
  const fs::path log = runDir.parent_path() / tag;
  run({o.multifluid, "render", scene, "--out", runDir.string(), "--frames", std::to_string(frame), "--samples", std::to_string(spp),
       "--resolution", fmt::format("{}x{}", o.width, o.height), "--threads", "2", "--set",
       std::string("render.denoise=") + (denoise ? "true" : "false")},
      log.string());
  std::smatch m;
  const std::string err = slurp(log.string() + ".err");
  if (!std::regex_search(err, m, std::regex(R"(rendered \(([0-9.]+) s each)")))
    throw std::runtime_error("no render time in " + log.string() + ".err");
  Render r{spp, std::stod(m[1]), (runDir.parent_path() / (tag + ".exr")).string()};
  const std::string name = fmt::format("{:04d}", frame);
  fs::rename(runDir / "render" / ("render." + name + ".exr"), r.exr);
  fs::remove(runDir / "render" / ("render." + name + ".png"));
  fs::remove(runDir / "records" / ("render." + name + ".txt"));
  return r;
}

/// Cycles: the exported .blend at `spp` samples, no denoiser, linear EXR.
Render renderCycles(const Options& o, const fs::path& blend, int frame, int spp) {
  const fs::path dir = blend.parent_path().parent_path();
  const std::string tag = fmt::format("cycles_{}", spp);
  const std::string setup = fmt::format(
      "import bpy\ns = bpy.context.scene\ns.cycles.samples = {}\ns.cycles.use_denoising = False\n"
      "s.cycles.use_adaptive_sampling = False\ns.render.threads_mode = 'FIXED'\ns.render.threads = 2\n"
      "s.render.resolution_x = {}\ns.render.resolution_y = {}\ns.render.resolution_percentage = 100\n"
      "s.render.image_settings.file_format = 'OPEN_EXR'\ns.render.image_settings.color_depth = '32'\n",
      spp, o.width, o.height);
  const fs::path script = dir / (tag + ".py");
  std::ofstream(script) << setup;
  run({"blender", "-b", blend.string(), "--python", script.string(), "-o", (dir / (tag + "_####")).string(), "-F", "OPEN_EXR", "-f",
       std::to_string(frame)},
      (dir / tag).string());
  // The last "Time:MM:SS.ss" of the frame's progress lines, on its "Finished" line.
  const std::string out = slurp((dir / tag).string() + ".out");
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(R"(Time:([0-9]+):([0-9.]+) \|[^\n]*\| Finished)")))
    throw std::runtime_error("no Cycles render time in " + (dir / tag).string() + ".out");
  return {spp, 60 * std::stod(m[1]) + std::stod(m[2]), (dir / fmt::format("{}_{:04d}.exr", tag, frame)).string()};
}

/// log-log interpolation through a ladder of (x, y) points sorted by x; NaN outside it (not
/// extrapolated).
double interpolate(const std::vector<std::pair<double, double>>& ladder, double x) {
  for (size_t k = 1; k < ladder.size(); ++k)
    if (x >= ladder[k - 1].first && x <= ladder[k].first) {
      const auto [x0, y0] = ladder[k - 1];
      const auto [x1, y1] = ladder[k];
      const double f = x1 > x0 ? std::log(x / x0) / std::log(x1 / x0) : 0;
      return std::exp(std::log(y0) + f * (std::log(y1) - std::log(y0)));
    }
  return std::nan("");
}

void benchFrame(const Options& o, const std::string& scene, int frame) {
  const fs::path dir = fs::path(o.work) / fmt::format("{}_{}", scene, frame), runDir = dir / "run";
  fs::create_directories(dir);
  fmt::print("\n{} frame {} ({}x{}): simulating and surfacing frames 0-{}\n", scene, frame, o.width, o.height, frame);
  std::fflush(stdout);
  run({o.multifluid, "run", scene, "--out", runDir.string(), "--frames", fmt::format("0-{}", frame), "--stages", "sim,surface",
       "--threads", "2", "--set", "surfacing.meshes=[\"ply\"]"},
      (dir / "run").string());
  run({o.multifluid, "export", "blender", runDir.string(), "--meshes", "ply"}, (dir / "export").string());
  const fs::path blend = runDir / (scene + ".blend");

  const Render oursRef = renderOurs(o, runDir, scene, frame, o.reference, false);
  const Render cyclesRef = renderCycles(o, blend, frame, o.reference);
  const mf::render::Image refOurs = mf::render::readImage(oursRef.exr), refCycles = mf::render::readImage(cyclesRef.exr);
  fmt::print("  references: ours {} spp in {:.1f} s, Cycles {} spp in {:.1f} s; the two differ by rel RMSE {:.3f}\n", o.reference,
             oursRef.seconds, o.reference, cyclesRef.seconds, relRmse(refCycles, refOurs));

  // Cycles' (time, error) and (error, time) ladders.
  std::vector<std::pair<double, double>> byTime, byError;
  fmt::print("  {:<16} {:>5} {:>9} {:>9}\n", "renderer", "spp", "time s", "rel RMSE");
  for (int spp : o.cycles) {
    const Render r = renderCycles(o, blend, frame, spp);
    const double e = relRmse(mf::render::readImage(r.exr), refCycles);
    byTime.push_back({r.seconds, e});
    byError.push_back({e, r.seconds});
    fmt::print("  {:<16} {:>5} {:>9.2f} {:>9.4f}\n", "Cycles", spp, r.seconds, e);
    std::fflush(stdout);
  }
  std::sort(byTime.begin(), byTime.end());
  std::sort(byError.begin(), byError.end());
  for (bool denoise : {false, true})
    for (int spp : o.ours) {
      const Render r = renderOurs(o, runDir, scene, frame, spp, denoise);
      const double e = relRmse(mf::render::readImage(r.exr), refOurs);
      const double c = interpolate(byTime, r.seconds), t = interpolate(byError, e);
      fmt::print("  {:<16} {:>5} {:>9.2f} {:>9.4f}   Cycles: {}; {}\n", denoise ? "ours, denoised" : "ours", spp, r.seconds, e,
                 std::isnan(c) ? fmt::format("no frame in {:.2f} s", r.seconds) : fmt::format("{:.4f} in that time ({:.2f}x ours)", c, c / e),
                 std::isnan(t) ? std::string("that error outside its ladder") : fmt::format("that error in {:.2f} s ({:.1f}x ours)", t, t / r.seconds));
      std::fflush(stdout);
    }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--multifluid") o.multifluid = next();
    else if (a == "--resolution") {
      const std::string v = next();
      if (std::sscanf(v.c_str(), "%dx%d", &o.width, &o.height) != 2) throw std::runtime_error("--resolution WxH");
    } else if (a == "--reference") o.reference = int(mf::bench::whole(a, next()));
    else if (a == "--ours") o.ours = numbers(a, next());
    else if (a == "--cycles") o.cycles = numbers(a, next());
    else if (a == "--work") o.work = next();
    else if (a == "--frames") {
      o.frames.clear();
      std::stringstream ss(next());
      for (std::string item; std::getline(ss, item, ',');) {
        const size_t c = item.find(':');
        if (c == std::string::npos) throw std::runtime_error("--frames SCENE:FRAME,...");
        o.frames.push_back({item.substr(0, c), int(mf::bench::whole(a, item.substr(c + 1)))});
      }
    } else {
      fmt::print(stderr, "usage: cycles_bench [--multifluid PATH] [--frames SCENE:F,...] [--resolution WxH] [--reference SPP] "
                         "[--ours SPP,...] [--cycles SPP,...] [--work DIR]\n");
      return 2;
    }
  }
  // The programs are started without a shell, found on PATH: put our multifluid's folder first.
  if (o.multifluid.find('/') != std::string::npos) {
    const fs::path p = fs::absolute(o.multifluid);
    const char* path = std::getenv("PATH");
    ::setenv("PATH", (p.parent_path().string() + ":" + (path ? path : "")).c_str(), 1);
    o.multifluid = p.filename().string();
  }
  if (mf::pipeline::findOnPath("blender").empty()) {
    fmt::print(stderr, "cycles_bench: blender is not on PATH (scripts/setup.sh --with-blender)\n");
    return 2;
  }
  if (o.work.empty()) o.work = (fs::temp_directory_path() / fmt::format("mf_cycles_bench_{}", ::getpid())).string();
  fmt::print("cycles_bench: work folder {}\n", o.work);
  try {
    for (const auto& [scene, frame] : o.frames) benchFrame(o, scene, frame);
  } catch (const std::exception& e) {
    fmt::print(stderr, "cycles_bench: {}\n", e.what());
    return 1;
  }
}
