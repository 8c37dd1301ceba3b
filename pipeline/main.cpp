// multifluid: runs scenes frame by frame through the stages sim -> surface -> render -> encode
// (and a quick particle preview), each also a subcommand on a frame range; `diff` compares two
// frame sequences; `report` measures accuracy and stability.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/report.h"
#include "sim/particle_io.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "render/image.h"
#include "render/preview.h"
#include "render/render_frame.h"
#include "surfacing/surface_frame.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

constexpr const char* kDefaultScene = "lava_lamp";
// With no argument at all, the default scene runs at demo quality: about ten minutes on 2 cores
// from nothing to an mp4 (the scene file itself asks for 60 s at 10 fps and 16 samples).
const std::vector<std::string> kDefaultDemoSettings = {"scene.end_time=12.0", "scene.frame_rate=5.0", "render.samples=8"};

void usage(std::FILE* to) {
  fmt::print(to,
             "usage: multifluid [run] [SCENE] [--out DIR] [--frames A-B] [--stages LIST] [--threads N] [--set key=value]...\n"
             "                  [--resolution WxH] [--samples N] [--preview-colour phase|temperature]\n"
             "       multifluid sim|surface|render|preview|encode SCENE [same options]\n"
             "       multifluid diff DIR_A DIR_B [--threshold T] [--fail-percent P] [--out DIFF_DIR]\n"
             "       multifluid validate SCENE [--set key=value]...\n"
             "       multifluid report accuracy|stability [--quick] [--out DIR]\n"
             "       multifluid scenes\n"
             "\n"
             "SCENE is a scene file (TOML) or the name of an embedded scene; with no argument at all the\n"
             "embedded '{}' scene runs into runs/{} at demo quality ({}).\n"
             "Stages: sim, surface, render, preview, encode\n"
             "(default for run: sim,surface,render,encode). Output in DIR (default runs/<scene>):\n"
             "particles/particles.NNNN.vdb (OpenVDB points), surface/surface.NNNN.vdb (level sets),\n"
             "mesh/ (if the scene asks for meshes), render/render.NNNN.exr|png, preview/preview.NNNN.png,\n"
             "<scene>.mp4, scene.toml (the resolved scene), checkpoint.bin, run.log.\n"
             "A re-run with the same scene and DIR resumes from the last checkpoint; finished frames of\n"
             "every stage are skipped. Surfacing frame N needs only particles.N.vdb; rendering it, only\n"
             "surface.N.vdb. diff exits non-zero when a frame has more than P % of pixels (default 1)\n"
             "differing by more than T (default 0.016, displayed values in [0, 1]) or a frame is missing.\n",
             kDefaultScene, kDefaultScene, fmt::join(kDefaultDemoSettings, ", "));
}

struct Options {
  std::string command = "run";
  std::string scene = kDefaultScene;
  std::string out;
  std::vector<std::string> sets;
  int firstFrame = 0, lastFrame = -1;
  int threads = 0;
  bool sim = true, surface = true, render = true, preview = false, encode = true;
  mf::render::PreviewColour previewColour = mf::render::PreviewColour::Phase;
  // diff
  std::string dirA, dirB;
  double threshold = 0.016, failPercent = 1;
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
fs::path renderFile(const fs::path& out, int f, const char* ext) { return out / "render" / fmt::format("render.{:04d}.{}", f, ext); }
fs::path previewFile(const fs::path& out, int f) { return out / "preview" / fmt::format("preview.{:04d}.png", f); }

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

std::string runRender(const Options& opt, const mf::Scene& scene, const fs::path& out) {
  const int lastFrame = lastFrameToRun(opt, scene);
  const auto t0 = Clock::now();
  int done = 0, skipped = 0, missing = 0;
  uint64_t rays = 0;
  double traceSeconds = 0;
  for (int f = opt.firstFrame; f <= lastFrame; ++f) {
    if (!fs::exists(surfaceFile(out, f))) {
      ++missing;
      continue;
    }
    const auto f0 = Clock::now();
    auto lastNote = Clock::now();
    auto progress = [&](int rows, int total) {
      if (seconds(Clock::now() - lastNote) < 5) return;
      lastNote = Clock::now();
      const double e = seconds(Clock::now() - f0);
      fmt::print(stderr, "  [render {:4d}] {:3d}% of rows, {} left in this frame\n", f, 100 * rows / total,
                 formatDuration(e / rows * (total - rows)));
    };
    const auto r = mf::render::renderFrame(surfaceFile(out, f).string(), scene, renderFile(out, f, "exr").string(),
                                           renderFile(out, f, "png").string(), f, progress);
    if (r.skipped) {
      ++skipped;
      continue;
    }
    ++done;
    rays += r.rays;
    traceSeconds += r.seconds;
    const double elapsed = seconds(Clock::now() - t0);
    fmt::print(stderr, "[render  {:4d}/{}] {}x{} x {} spp, {} triangles, {:.2f} Mrays/s, {:.2f} s  elapsed {}  left ~{}\n", f,
               lastFrame, scene.render.width, scene.render.height, scene.render.samples, r.triangles,
               r.seconds > 0 ? r.rays / r.seconds / 1e6 : 0.0, seconds(Clock::now() - f0), formatDuration(elapsed),
               formatDuration(elapsed / (f - opt.firstFrame + 1) * (lastFrame - f)));
  }
  const double total = seconds(Clock::now() - t0);
  if (missing > 0) fmt::print(stderr, "render: {} frame(s) have no surface file yet (run the surface stage)\n", missing);
  return fmt::format("  render        {:>8.2f} s   {} frame(s) rendered ({:.2f} s each, {:.2f} Mrays/s), {} already done\n", total,
                     done, done > 0 ? total / done : 0.0, traceSeconds > 0 ? rays / traceSeconds / 1e6 : 0.0, skipped);
}

std::string runPreview(const Options& opt, const mf::Scene& scene, const fs::path& out) {
  const int lastFrame = lastFrameToRun(opt, scene);
  const auto t0 = Clock::now();
  int done = 0, skipped = 0;
  for (int f = opt.firstFrame; f <= lastFrame; ++f) {
    if (!fs::exists(particleFile(out, f))) continue;
    const auto r = mf::render::renderPreview(particleFile(out, f).string(), scene, previewFile(out, f).string(), opt.previewColour);
    if (r.skipped) {
      ++skipped;
      continue;
    }
    ++done;
    if (seconds(Clock::now() - t0) > 2 || f == lastFrame)
      fmt::print(stderr, "[preview {:4d}/{}] {} particles, {:.2f} s\n", f, lastFrame, r.particles, r.seconds);
  }
  const double total = seconds(Clock::now() - t0);
  return fmt::format("  preview       {:>8.2f} s   {} frame(s) drawn, {} already done\n", total, done, skipped);
}

/// H.264 (yuv420p, even sizes) of the rendered frames, or of the previews if nothing is rendered.
std::string runEncode(const Options& opt, const mf::Scene& scene, const fs::path& out) {
  const int lastFrame = lastFrameToRun(opt, scene);
  const auto t0 = Clock::now();
  struct Source {
    const char* kind;
    std::function<fs::path(int)> file;
    const char* pattern;
  };
  const Source sources[] = {{"rendered", [&](int f) { return renderFile(out, f, "png"); }, "render/render.%04d.png"},
                            {"preview", [&](int f) { return previewFile(out, f); }, "preview/preview.%04d.png"}};
  const Source* used = nullptr;
  int first = -1, count = 0;
  for (const Source& src : sources) {
    first = -1, count = 0;
    for (int f = opt.firstFrame; f <= lastFrame; ++f) {
      if (!fs::exists(src.file(f))) {
        if (first >= 0) break;  // the movie is the first unbroken run of frames
        continue;
      }
      if (first < 0) first = f;
      ++count;
    }
    if (count > 0) {
      used = &src;
      break;
    }
  }
  if (count == 0) return "  encode            -      no rendered or preview frames to encode\n";
  if (std::system("command -v ffmpeg > /dev/null 2>&1") != 0)
    throw std::runtime_error("encode: ffmpeg was not found on PATH (Debian: apt-get install ffmpeg; scripts/setup.sh installs it)");
  const fs::path movie = out / (scene.name + ".mp4");
  const fs::path tmp = out / (scene.name + ".tmp.mp4");
  const std::string command = fmt::format(
      "ffmpeg -y -loglevel error -framerate {} -start_number {} -i '{}' -frames:v {} -c:v libx264 -preset medium -crf 18 "
      "-pix_fmt yuv420p -vf 'scale=trunc(iw/2)*2:trunc(ih/2)*2' -fflags +bitexact -flags:v +bitexact -map_metadata -1 '{}'",
      scene.frameRate, first, (out / used->pattern).string(), count, tmp.string());
  if (std::system(command.c_str()) != 0) throw std::runtime_error("encode: ffmpeg failed: " + command);
  fs::rename(tmp, movie);
  const double total = seconds(Clock::now() - t0);
  fmt::print(stderr, "[encode] {} {} frames from {} -> {}\n", count, used->kind, first, movie.string());
  return fmt::format("  encode        {:>8.2f} s   {} {} frame(s) -> {}\n", total, count, used->kind, movie.string());
}

int runStages(const Options& opt) {
  const mf::Scene scene = mf::loadScene(opt.scene, opt.sets);
  const fs::path out = opt.out.empty() ? fs::path("runs") / scene.name : fs::path(opt.out);
  fs::create_directories(out);
  writeTextAtomically(out / "scene.toml", scene.sourceText);
  std::string summary;
  if (opt.sim) summary += runSimulation(opt, scene, out);
  if (summary.empty()) summary = fmt::format("\nsummary for {}\n", scene.name);
  if (opt.surface) summary += runSurfacing(opt, scene, out);
  if (opt.render) summary += runRender(opt, scene, out);
  if (opt.preview) summary += runPreview(opt, scene, out);
  if (opt.encode) summary += runEncode(opt, scene, out);
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

/// Compares the images of two frame sequences by name (or two image files).
int diffSequences(const Options& opt) {
  std::vector<std::pair<fs::path, fs::path>> pairs;
  std::vector<std::string> missing;
  auto isImage = [](const fs::path& p) { return p.extension() == ".png" || p.extension() == ".exr"; };
  if (fs::is_regular_file(opt.dirA) && fs::is_regular_file(opt.dirB)) {
    pairs.push_back({opt.dirA, opt.dirB});
  } else {
    for (const auto& dir : {opt.dirA, opt.dirB})
      if (!fs::is_directory(dir)) throw std::runtime_error("diff: " + dir + " is not a directory");
    std::vector<fs::path> names;
    for (const auto& e : fs::directory_iterator(opt.dirA))
      if (isImage(e.path())) names.push_back(e.path().filename());
    for (const auto& e : fs::directory_iterator(opt.dirB))
      if (isImage(e.path()) && !fs::exists(fs::path(opt.dirA) / e.path().filename()))
        missing.push_back(e.path().filename().string() + " (only in " + opt.dirB + ")");
    std::sort(names.begin(), names.end());
    for (const auto& n : names) {
      if (fs::exists(fs::path(opt.dirB) / n)) pairs.push_back({fs::path(opt.dirA) / n, fs::path(opt.dirB) / n});
      else missing.push_back(n.string() + " (only in " + opt.dirA + ")");
    }
  }
  const fs::path diffDir = opt.out.empty() ? fs::path("diff") : fs::path(opt.out);
  int failed = 0;
  fmt::print("{:<28} {:>10} {:>10} {:>10} {:>9}  result\n", "frame", "mean", "rms", "max", "failed%");
  for (const auto& [a, b] : pairs) {
    mf::render::Image difference;
    const auto d = mf::render::compareImages(mf::render::readImage(a.string()), mf::render::readImage(b.string()), opt.threshold,
                                             &difference);
    const bool pass = d.passes(opt.failPercent);
    if (d.sizeMismatch) {
      fmt::print("{:<28} sizes differ  FAIL\n", a.filename().string());
    } else {
      fmt::print("{:<28} {:>10.5f} {:>10.5f} {:>10.5f} {:>8.3f}%  {}\n", a.filename().string(), d.meanError, d.rmsError,
                 d.maxError, d.failedPercent(), pass ? "ok" : "FAIL");
      if (d.failedPixels > 0) {
        fs::create_directories(diffDir);
        // Differences scaled x10 so that small ones are visible.
        for (float& v : difference.rgb) v = mf::render::srgbToLinear(std::min(1.0f, 10 * v));
        mf::render::writeImage((diffDir / (a.stem().string() + ".diff.png")).string(), difference);
      }
    }
    failed += pass ? 0 : 1;
  }
  for (const auto& m : missing) fmt::print("missing: {}\n", m);
  fmt::print("{} frame(s) compared, {} failed, {} missing (threshold {}, fail above {}% of pixels){}\n", pairs.size(), failed,
             missing.size(), opt.threshold, opt.failPercent,
             failed > 0 ? fmt::format("; difference images in {}", diffDir.string()) : "");
  return failed > 0 || !missing.empty() || pairs.empty() ? 1 : 0;
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
  if (args.empty()) opt.sets = kDefaultDemoSettings;
  if (!args.empty() && args[0] == "report") {
    try {
      return mf::report::runReportCommand(std::vector<std::string>(args.begin() + 1, args.end()));
    } catch (const std::exception& e) {
      fmt::print(stderr, "multifluid report: {}\n", e.what());
      return 1;
    }
  }
  size_t k = 0;
  const std::vector<std::string> commands = {"run", "sim", "surface", "render", "preview", "encode", "diff", "validate", "scenes"};
  if (k < args.size() && std::find(commands.begin(), commands.end(), args[k]) != commands.end()) opt.command = args[k++];
  const std::vector<std::string> stageNames = {"sim", "surface", "render", "preview", "encode"};
  if (std::find(stageNames.begin(), stageNames.end(), opt.command) != stageNames.end()) {
    // A stage subcommand runs that stage alone.
    opt.sim = opt.command == "sim", opt.surface = opt.command == "surface", opt.render = opt.command == "render";
    opt.preview = opt.command == "preview", opt.encode = opt.command == "encode";
  }
  bool haveScene = false;
  std::vector<std::string> positional;
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
      opt.sim = opt.surface = opt.render = opt.preview = opt.encode = false;
      std::stringstream ss(value());
      for (std::string stage; std::getline(ss, stage, ',');) {
        if (stage == "sim") opt.sim = true;
        else if (stage == "surface") opt.surface = true;
        else if (stage == "render") opt.render = true;
        else if (stage == "preview") opt.preview = true;
        else if (stage == "encode") opt.encode = true;
        else {
          fmt::print(stderr, "multifluid: unknown stage '{}' (stages: sim, surface, render, preview, encode)\n", stage);
          return 2;
        }
      }
    } else if (a == "--resolution") {
      const std::string v = value();
      int w = 0, h = 0;
      if (std::sscanf(v.c_str(), "%dx%d", &w, &h) != 2 || w < 8 || h < 8) {
        fmt::print(stderr, "multifluid: --resolution takes WxH, each at least 8 (e.g. 320x180)\n");
        return 2;
      }
      opt.sets.push_back(fmt::format("render.width={}", w));
      opt.sets.push_back(fmt::format("render.height={}", h));
    } else if (a == "--samples") {
      opt.sets.push_back("render.samples=" + value());
    } else if (a == "--preview-colour" || a == "--preview-color") {
      const std::string v = value();
      if (v == "phase") opt.previewColour = mf::render::PreviewColour::Phase;
      else if (v == "temperature") opt.previewColour = mf::render::PreviewColour::Temperature;
      else {
        fmt::print(stderr, "multifluid: --preview-colour is phase or temperature\n");
        return 2;
      }
    } else if (a == "--threshold") {
      opt.threshold = std::atof(value().c_str());
    } else if (a == "--fail-percent") {
      opt.failPercent = std::atof(value().c_str());
    } else if (a == "--frames") {
      if (!parseFrames(value(), opt.firstFrame, opt.lastFrame)) {
        fmt::print(stderr, "multifluid: --frames takes A-B with 0 <= A <= B, or a single frame\n");
        return 2;
      }
    } else if (!a.empty() && a[0] == '-') {
      fmt::print(stderr, "multifluid: unknown option {}\n", a);
      usage(stderr);
      return 2;
    } else if (opt.command == "diff") {
      positional.push_back(a);
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
    if (opt.command == "diff") {
      if (positional.size() != 2) {
        fmt::print(stderr, "multifluid: diff takes two directories (or two image files)\n");
        return 2;
      }
      opt.dirA = positional[0], opt.dirB = positional[1];
      return diffSequences(opt);
    }
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
