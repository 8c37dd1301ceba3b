// multifluid: runs scenes frame by frame. Today the stage is the simulation (particles per frame
// as OpenVDB points, exact checkpoints so a killed run resumes bit for bit).
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/report.h"
#include "sim/particle_io.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "surfacing/surface_frame.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

constexpr const char* kDefaultScene = "dam_break";

void usage(std::FILE* to) {
  fmt::print(to,
             "usage: multifluid [run] [SCENE] [--out DIR] [--frames A-B] [--stages sim,surface] [--threads N] [--set key=value]...\n"
             "       multifluid sim|surface SCENE [same options]\n"
             "       multifluid validate SCENE [--set key=value]...\n"
             "       multifluid scenes\n"
             "\n"
             "SCENE is a scene file (TOML) or the name of an embedded scene; with no argument at all the\n"
             "embedded '{}' scene runs into runs/{}. Output: DIR/particles/particles.NNNN.vdb (OpenVDB\n"
             "points), DIR/surface/surface.NNNN.vdb (level sets), DIR/mesh/ (if the scene asks for meshes),\n"
             "DIR/scene.toml (the resolved scene), DIR/checkpoint.bin, DIR/run.log.\n"
             "A re-run with the same scene and DIR resumes from the last checkpoint; finished surface\n"
             "frames are skipped. Surfacing frame N needs only particles.N.vdb.\n",
             kDefaultScene, kDefaultScene);
}

struct Options {
  std::string command = "run";
  std::string scene = kDefaultScene;
  std::string out;
  std::vector<std::string> sets;
  int firstFrame = 0, lastFrame = -1;
  int threads = 0;
  bool sim = true, surface = true;
};

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

std::string formatDuration(double s) {
  if (s < 60) return fmt::format("{:.1f}s", s);
  return fmt::format("{}m{:02d}s", int(s / 60), int(s) % 60);
}

void writeTextAtomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream o(tmp, std::ios::binary | std::ios::trunc);
    o << text;
    if (!o) throw std::runtime_error("cannot write " + tmp.string());
  }
  fs::rename(tmp, path);
}

// The output layout, in one place.
fs::path particleFile(const fs::path& out, int f) { return out / "particles" / fmt::format("particles.{:04d}.vdb", f); }
fs::path surfaceFile(const fs::path& out, int f) { return out / "surface" / fmt::format("surface.{:04d}.vdb", f); }

int lastFrameToRun(const Options& opt, const mf::Scene& scene) {
  return opt.lastFrame >= 0 ? std::min(opt.lastFrame, scene.lastFrame()) : scene.lastFrame();
}

std::string runSimulation(const Options& opt, const mf::Scene& scene, const fs::path& out) {
  fs::create_directories(out / "particles");
  const int lastFrame = lastFrameToRun(opt, scene);
  const fs::path checkpoint = out / "checkpoint.bin";

  const auto t0 = Clock::now();
  mf::Simulation sim(scene);
  double tInit = seconds(Clock::now() - t0), tSim = 0, tWrite = 0, tCheckpoint = 0;
  mf::FrameInfo info;
  info.sceneName = scene.name;
  info.particleSpacing = scene.solver.particleSpacing;
  for (const auto& p : scene.phases) info.phaseNames.push_back(p.name);

  auto writeFrame = [&](int f) {
    if (f < opt.firstFrame) return;
    const auto w0 = Clock::now();
    info.frame = f;
    info.time = sim.time();
    mf::writeParticleFrame(particleFile(out, f).string(), sim.particles(), info);
    tWrite += seconds(Clock::now() - w0);
  };
  auto saveCheckpoint = [&](int f) {
    const auto c0 = Clock::now();
    sim.saveCheckpoint(checkpoint.string(), f);
    tCheckpoint += seconds(Clock::now() - c0);
  };

  int startFrame = 0;
  bool resumed = false;
  if (fs::exists(checkpoint)) {
    const int checkpointFrame = sim.loadCheckpoint(checkpoint.string());
    // Frames before the checkpoint that this run asks for must exist (an earlier run may have
    // written only a later range); otherwise simulate again from the start: same bits.
    int missing = -1;
    for (int f = opt.firstFrame; f <= std::min(checkpointFrame, lastFrame) && missing < 0; ++f)
      if (!fs::exists(particleFile(out, f))) missing = f;
    if (missing < 0) {
      startFrame = checkpointFrame + 1;
      resumed = true;
      fmt::print(stderr, "resuming {} from its checkpoint at frame {} (t = {:.4f} s)\n", out.string(), checkpointFrame, sim.time());
    } else {
      fmt::print(stderr, "frame {} was never written in {}: simulating again from frame 0\n", missing, out.string());
      sim = mf::Simulation(scene);
    }
  }
  if (!resumed) {
    writeFrame(0);
    saveCheckpoint(0);
    startFrame = 1;
  }
  const size_t n0 = sim.particles().size();
  fmt::print(stderr, "{}: {} particles, {} boundary samples, h = {:.4g} m, frames {}..{} at {} fps -> {}\n", scene.name, n0,
             sim.boundary().size(), sim.kernels().h, opt.firstFrame, lastFrame, scene.frameRate, out.string());

  const uint64_t steps0 = sim.stepCount();
  double particleSteps = 0;
  const auto loopStart = Clock::now();
  for (int f = startFrame; f <= lastFrame; ++f) {
    const auto s0 = Clock::now();
    auto lastNote = Clock::now();
    sim.advanceTo(f / scene.frameRate, [&](const mf::Simulation& s) {
      particleSteps += double(s.particles().size());
      // Long frames (large scenes) report inside the frame too, every few seconds.
      if (seconds(Clock::now() - lastNote) > 5) {
        lastNote = Clock::now();
        fmt::print(stderr, "  [frame {:4d}] t = {:.5f} s of {:.5f} s, step {}, dt {:.2e} s\n", f, s.time(), f / scene.frameRate,
                   s.stepCount(), s.counters().lastDt);
      }
    });
    tSim += seconds(Clock::now() - s0);
    writeFrame(f);
    saveCheckpoint(f);
    const double elapsed = seconds(Clock::now() - loopStart);
    const double eta = elapsed / (f - startFrame + 1) * (lastFrame - f);
    fmt::print(stderr, "[frame {:4d}/{}] t = {:.4f} s  steps {:6d}  dt {:.2e} s  particles {}  elapsed {}  left ~{}\n", f,
               lastFrame, sim.time(), sim.stepCount(), sim.counters().lastDt, sim.particles().size(),
               formatDuration(elapsed), formatDuration(eta));
  }

  const auto& c = sim.counters();
  const uint64_t steps = sim.stepCount() - steps0;
  std::string summary = fmt::format(
      "\nsummary for {} ({} threads requested)\n"
      "  stage            time\n"
      "  setup         {:>8.2f} s\n"
      "  simulate      {:>8.2f} s   {} steps, {:.0f} ns per particle-step\n"
      "  write frames  {:>8.2f} s\n"
      "  checkpoints   {:>8.2f} s\n"
      "  particles: {} at start, {} now, {} left the domain; watchdog retries: {}; wall clamps: {}; max compression {:.2f}%\n",
      scene.name, opt.threads > 0 ? std::to_string(opt.threads) : "all", tInit, tSim, steps,
      particleSteps > 0 ? tSim * 1e9 / particleSteps : 0.0, tWrite, tCheckpoint, n0, sim.particles().size(),
      c.removedOutOfDomain, c.retries, c.wallClamps, 100 * c.maxDensityError);
  return summary;
}

std::string runSurfacing(const Options& opt, const mf::Scene& scene, const fs::path& out) {
  const int lastFrame = lastFrameToRun(opt, scene);
  const auto t0 = Clock::now();
  int done = 0, skipped = 0, missing = 0;
  size_t voxels = 0;
  for (int f = opt.firstFrame; f <= lastFrame; ++f) {
    const fs::path particles = particleFile(out, f);
    if (!fs::exists(particles)) {
      ++missing;
      continue;
    }
    const auto f0 = Clock::now();
    const auto r = mf::surfacing::surfaceFrame(particles.string(), scene,
                                               surfaceFile(out, f).string(),
                                               (out / "mesh").string(), f);
    if (r.skipped) {
      ++skipped;
      continue;
    }
    ++done;
    voxels += r.activeVoxels;
    const double elapsed = seconds(Clock::now() - t0);
    fmt::print(stderr, "[surface {:4d}/{}] {} phase(s), {} active voxels, {:.2f} s  elapsed {}  left ~{}\n", f, lastFrame,
               scene.surfacing.phases.size(), r.activeVoxels, seconds(Clock::now() - f0), formatDuration(elapsed),
               formatDuration(elapsed / (f - opt.firstFrame + 1) * (lastFrame - f)));
  }
  const double total = seconds(Clock::now() - t0);
  if (missing > 0) fmt::print(stderr, "surface: {} frame(s) have no particle file yet (run the sim stage)\n", missing);
  return fmt::format("  surface       {:>8.2f} s   {} frame(s) surfaced ({:.2f} s each, {:.0f} active voxels each), {} already done\n",
                     total, done, done > 0 ? total / done : 0.0, done > 0 ? double(voxels) / done : 0.0, skipped);
}

int runStages(const Options& opt) {
  const mf::Scene scene = mf::loadScene(opt.scene, opt.sets);
  const fs::path out = opt.out.empty() ? fs::path("runs") / scene.name : fs::path(opt.out);
  fs::create_directories(out);
  writeTextAtomically(out / "scene.toml", scene.sourceText);
  std::string summary;
  if (opt.sim) summary += runSimulation(opt, scene, out);
  if (opt.surface) {
    if (summary.empty()) summary = fmt::format("\nsummary for {}\n", scene.name);
    summary += runSurfacing(opt, scene, out);
  }
  fmt::print(stderr, "{}", summary);
  std::ofstream(out / "run.log", std::ios::app) << summary;
  return 0;
}

int validate(const Options& opt) {
  const mf::Scene scene = mf::loadScene(opt.scene, opt.sets);
  fmt::print("{}: valid scene '{}', {} phase(s), {} solid(s), {} fluid block(s), effects:", scene.sourceFile, scene.name,
             scene.phases.size(), scene.solids.size(), scene.fluids.size());
  for (const auto& e : scene.effects) fmt::print(" {}", e.name);
  fmt::print("\n");
  return 0;
}

bool parseFrames(const std::string& s, int& a, int& b) {
  const size_t dash = s.find('-');
  try {
    if (dash == std::string::npos) {
      a = b = std::stoi(s);
    } else {
      a = std::stoi(s.substr(0, dash));
      b = std::stoi(s.substr(dash + 1));
    }
  } catch (...) {
    return false;
  }
  return a >= 0 && b >= a;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && args[0] == "report") {
    try {
      return mf::report::runReportCommand(std::vector<std::string>(args.begin() + 1, args.end()));
    } catch (const std::exception& e) {
      fmt::print(stderr, "multifluid report: {}\n", e.what());
      return 1;
    }
  }
  size_t k = 0;
  if (k < args.size() && (args[k] == "run" || args[k] == "sim" || args[k] == "surface" || args[k] == "validate" ||
                          args[k] == "scenes"))
    opt.command = args[k++];
  if (opt.command == "sim") opt.surface = false;
  if (opt.command == "surface") opt.sim = false;
  bool haveScene = false;
  for (; k < args.size(); ++k) {
    const std::string& a = args[k];
    auto value = [&]() -> std::string {
      if (k + 1 >= args.size()) {
        fmt::print(stderr, "multifluid: {} needs a value\n", a);
        std::exit(2);
      }
      return args[++k];
    };
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "--out") {
      opt.out = value();
    } else if (a == "--set") {
      opt.sets.push_back(value());
    } else if (a == "--threads") {
      opt.threads = std::atoi(value().c_str());
      if (opt.threads < 1) {
        fmt::print(stderr, "multifluid: --threads must be at least 1\n");
        return 2;
      }
    } else if (a == "--stages") {
      opt.sim = opt.surface = false;
      std::stringstream ss(value());
      for (std::string stage; std::getline(ss, stage, ',');) {
        if (stage == "sim") opt.sim = true;
        else if (stage == "surface") opt.surface = true;
        else {
          fmt::print(stderr, "multifluid: unknown stage '{}' (stages: sim, surface)\n", stage);
          return 2;
        }
      }
    } else if (a == "--frames") {
      if (!parseFrames(value(), opt.firstFrame, opt.lastFrame)) {
        fmt::print(stderr, "multifluid: --frames takes A-B with 0 <= A <= B, or a single frame\n");
        return 2;
      }
    } else if (!a.empty() && a[0] == '-') {
      fmt::print(stderr, "multifluid: unknown option {}\n", a);
      usage(stderr);
      return 2;
    } else if (!haveScene) {
      opt.scene = a;
      haveScene = true;
    } else {
      fmt::print(stderr, "multifluid: unexpected argument {}\n", a);
      return 2;
    }
  }
  std::unique_ptr<tbb::global_control> threads;
  if (opt.threads > 0) threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, opt.threads);

  try {
    if (opt.command == "scenes") {
      for (const auto& n : mf::embeddedSceneNames()) fmt::print("{}\n", n);
      return 0;
    }
    if (opt.command == "validate") return validate(opt);
    return runStages(opt);
  } catch (const mf::SceneError& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 2;
  } catch (const mf::NumericalInstability& e) {
    fmt::print(stderr, "multifluid: {}\nNo frame was written for the failed step; the last checkpoint is intact.\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    fmt::print(stderr, "multifluid: {}\n", e.what());
    return 1;
  }
}
