#include "pipeline/stages.h"

#include <unistd.h>

#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <thread>

#include "pipeline/folder_lock.h"
#include "pipeline/process.h"
#include "pipeline/progress.h"
#include "pipeline/report_util.h"
#include "pipeline/run_folder.h"
#include "render/render_frame.h"
#include "sim/file_util.h"
#include "sim/particle_io.h"
#include "sim/run_warnings.h"
#include "sim/simulation.h"
#include "surfacing/surface_frame.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace mf::pipeline {

namespace {

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

using report::formatDuration;

// The output layout, in one place.
fs::path particleFile(const fs::path& out, int f) { return out / "particles" / fmt::format("particles.{:04d}.vdb", f); }
fs::path surfaceFile(const fs::path& out, int f) { return out / "surface" / fmt::format("surface.{:04d}.vdb", f); }
fs::path renderFile(const fs::path& out, int f, const char* ext) { return out / "render" / fmt::format("render.{:04d}.{}", f, ext); }
fs::path previewFile(const fs::path& out, int f) { return out / "preview" / fmt::format("preview.{:04d}.png", f); }

int lastFrameToRun(const StageOptions& opt, const Scene& scene) {
  return opt.lastFrame >= 0 ? std::min(opt.lastFrame, scene.lastFrame()) : scene.lastFrame();
}

/// The input of a downstream stage: true if `stage`'s frame is finished; false if it was never
/// finished (no record, no file); throws naming the file if its record no longer matches it.
bool inputReady(const FrameRecords& records, const std::string& stage, int frame, const fs::path& file, const char* redo) {
  std::string why;
  if (records.verify(stage, frame, &why)) return true;
  std::error_code ec;
  if (!fs::exists(records.recordFile(stage, frame), ec)) return false;
  throw std::runtime_error(fmt::format("{}: {}; run the {} stage again to rewrite it", file.string(), why, redo));
}

/// inputReady, waiting up to `opt.waitForInputSeconds` (polling) for a frame another process is
/// still making; with a wait, a frame still missing at the end is an error naming it.
bool awaitInput(const StageOptions& opt, const FrameRecords& records, const std::string& stage, int frame, const fs::path& file,
                const char* redo) {
  const auto start = Clock::now();
  bool noted = false;
  while (!inputReady(records, stage, frame, file, redo)) {
    if (opt.waitForInputSeconds <= 0) return false;
    const double waited = seconds(Clock::now() - start);
    if (waited >= opt.waitForInputSeconds)
      throw InputNotReady(fmt::format("frame {}: no finished {} frame after waiting {:.0f} s (--wait-for-input): {} has no "
                                      "completion record; is the {} stage running?",
                                      frame, stage, waited, file.string(), redo));
    if (!noted) fmt::print(stderr, "frame {}: waiting up to {:.0f} s for {}\n", frame, opt.waitForInputSeconds, file.string());
    noted = true;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  return true;
}

/// The scene copy is rewritten only when it changes, and through a temporary of this process's
/// own: farm tasks that start together find it equal, or each write a whole file of their own.
void writeSceneCopy(const Scene& scene, const fs::path& out) {
  const fs::path file = out / "scene.toml";
  std::ifstream in(file, std::ios::binary);
  const std::string old((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.is_open() && old == scene.sourceText) return;
  const fs::path mine = out / fmt::format("scene.toml.tmp{}", ::getpid());
  writeFileAtomically(mine.string(), scene.sourceText);
  fs::rename(mine, file);
}

// SIGTERM / SIGUSR1 during the simulation: stop at the next step (see StopRequested).
std::atomic<int> stopSignal{0};
extern "C" void onStopSignal(int sig) { stopSignal.store(sig); }

struct StopSignals {
  struct sigaction oldTerm {}, oldUsr1 {};
  StopSignals() {
    stopSignal.store(0);
    struct sigaction sa {};
    sa.sa_handler = onStopSignal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, &oldTerm);
    sigaction(SIGUSR1, &sa, &oldUsr1);
  }
  ~StopSignals() {
    sigaction(SIGTERM, &oldTerm, nullptr);
    sigaction(SIGUSR1, &oldUsr1, nullptr);
  }
};

/// Deletes a stage's frame so that it is made afresh: the record first, then the files.
void discardFrame(const FrameRecords& records, const std::string& stage, int frame, const std::vector<fs::path>& files) {
  records.remove(stage, frame);
  std::error_code ec;
  for (const fs::path& f : records.files(stage, frame)) fs::remove(f, ec);
  for (const fs::path& f : files) fs::remove(f, ec);
}

std::string runSimulation(const StageOptions& opt, const Scene& scene, const fs::path& out, const FrameRecords& records) {
  fs::create_directories(out / "particles");
  const int lastFrame = lastFrameToRun(opt, scene);
  const fs::path checkpoint = out / "checkpoint.bin";

  const auto t0 = Clock::now();
  Simulation sim(scene);
  const std::vector<size_t> seeded = phaseCounts(sim);  // before any checkpoint is loaded
  double tInit = seconds(Clock::now() - t0), tSim = 0, tWrite = 0, tCheckpoint = 0;
  FrameInfo info = frameInfoFor(scene);

  auto writeFrame = [&](int f) {
    if (f < opt.firstFrame) return;
    const auto w0 = Clock::now();
    info.frame = f;
    info.time = sim.time();
    records.remove("particles", f);
    writeParticleFrame(particleFile(out, f).string(), sim.particles(), info);
    records.write("particles", f, {particleFile(out, f)});
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
    // Frames before the checkpoint that this run asks for must be finished (an earlier run may
    // have written only a later range, or a file may be damaged); else simulate again from the
    // start: same bits.
    int missing = -1;
    std::string why;
    for (int f = opt.firstFrame; f <= std::min(checkpointFrame, lastFrame) && missing < 0; ++f)
      if (!records.verify("particles", f, &why)) missing = f;
    if (missing < 0) {
      startFrame = checkpointFrame + 1;
      resumed = true;
      fmt::print(stderr, "resuming {} from its checkpoint at frame {} (t = {:.4f} s)\n", out.string(), checkpointFrame, sim.time());
    } else {
      fmt::print(stderr, "frame {} was never finished in {} ({}): simulating again from frame 0\n", missing, out.string(), why);
      sim = Simulation(scene);
    }
  }
  // The scene as run, written once the checkpoint (if any) has been accepted as this scene's.
  writeSceneCopy(scene, out);
  if (!resumed) {
    writeFrame(0);
    saveCheckpoint(0);
    startFrame = 1;
  }
  const size_t n0 = sim.particles().size();
  fmt::print(stderr, "{}: {} particles, {} boundary samples, h = {:.4g} m, frames {}..{} at {} fps -> {}\n", scene.name, n0,
             sim.boundary().size(), sim.kernels().h, opt.firstFrame, lastFrame, scene.frameRate, out.string());

  const uint64_t steps0 = sim.stepCount();
  const double time0 = sim.time();
  const uint64_t density0 = sim.counters().pressureIterations, divergence0 = sim.counters().divergenceIterations;
  const uint64_t passes0 = sim.counters().compressionPasses;
  double particleSteps = 0;
  const StopSignals stopSignals;
  const auto loopStart = Clock::now();
  // The ETA follows simulated time at the recent cost, not frames done: emitters make late
  // frames dearer (pour_glass first promised 45 s for 3 min).
  StageProgress progress("sim", sim.time(), lastFrame / scene.frameRate, double(sim.particles().size()));
  for (int f = startFrame; f <= lastFrame; ++f) {
    const auto s0 = Clock::now();
    auto lastNote = Clock::now();
    const uint64_t frameStart = sim.stepCount();
    sim.advanceTo(f / scene.frameRate, [&](const Simulation& s) {
      particleSteps += double(s.particles().size());
      if (const int sig = stopSignal.load())
        throw StopRequested(fmt::format("stopped by {} during frame {} (t = {:.6g} s); the checkpoint of frame {} is intact: "
                                        "run again to resume",
                                        sig == SIGTERM ? "SIGTERM" : "SIGUSR1", f, s.time(), f - 1),
                            sig);
      // A time step that has collapsed would step on for ever: stop, naming what sets it.
      const uint64_t stepsInFrame = s.stepCount() - frameStart;
      if (opt.maxStepsPerFrame > 0 && double(stepsInFrame) > opt.maxStepsPerFrame)
        throw NumericalInstability(fmt::format(
            "frame {}: {} steps without reaching t = {:.6g} s (step {}, t = {:.6g} s, dt = {:.3g} s, set by {}); the time "
            "step has collapsed. Change that parameter, or raise the bound with --max-steps-per-frame",
            f, stepsInFrame, f / scene.frameRate, s.stepCount(), s.time(), s.counters().lastDt, s.dtLimiter()));
      // Long frames (large scenes) report inside the frame too: every few seconds, or on a
      // terminal as the progress line twice a second.
      if (seconds(Clock::now() - lastNote) > (progress.terminal() ? 0.5 : 5)) {
        lastNote = Clock::now();
        if (progress.terminal())
          progress.update(s.time(), double(s.particles().size()), fmt::format("frame {}/{} t = {:.4f} s  particles {}  step {}", f, lastFrame, s.time(),
                                                s.particles().size(), s.stepCount()));
        else
          fmt::print(stderr, "  [frame {:4d}] t = {:.5f} s of {:.5f} s, step {}, dt {:.2e} s\n", f, s.time(), f / scene.frameRate,
                     s.stepCount(), s.counters().lastDt);
      }
    });
    tSim += seconds(Clock::now() - s0);
    writeFrame(f);
    saveCheckpoint(f);
    const double elapsed = seconds(Clock::now() - loopStart);
    const std::string detail = fmt::format("frame {}/{} t = {:.4f} s  particles {}  step {}", f, lastFrame, sim.time(),
                                           sim.particles().size(), sim.stepCount());
    progress.update(sim.time(), double(sim.particles().size()), detail);
    if (!progress.terminal())
      fmt::print(stderr, "[frame {:4d}/{}] t = {:.4f} s  steps {:6d}  dt {:.2e} s  particles {}  elapsed {}  left ~{}\n", f,
                 lastFrame, sim.time(), sim.stepCount(), sim.counters().lastDt, sim.particles().size(), formatDuration(elapsed),
                 formatDuration(progress.eta()));
  }
  progress.finish();

  const auto& c = sim.counters();
  const uint64_t steps = sim.stepCount() - steps0;
  return fmt::format(
      "\nsummary for {} ({} threads requested)\n"
      "  stage            time\n"
      "  setup         {:>8.2f} s\n"
      "  simulate      {:>8.2f} s   {} steps, {:.0f} ns per particle-step\n"
      "  write frames  {:>8.2f} s\n"
      "  checkpoints   {:>8.2f} s\n"
      "  particles: {} at start, {} now, {} left the domain; watchdog retries: {}; wall clamps: {}; max compression {:.2f}%\n"
      "  {}; {:.1f} s of wall time per simulated second\n",
      scene.name, opt.threads > 0 ? std::to_string(opt.threads) : "all", tInit, tSim, steps,
      particleSteps > 0 ? tSim * 1e9 / particleSteps : 0.0, tWrite, tCheckpoint, n0, sim.particles().size(),
      c.removedOutOfDomain, c.retries, c.wallClamps, 100 * c.maxDensityError,
      scene.solver.pressure == PressureSolverChoice::WCSPH
          ? std::string("pressure: wcsph")
          : fmt::format("pressure: dfsph ({}), {:.1f} iterations per step ({:.1f} constant-density with the passes, {:.1f} divergence-free), "
                        "{} compression passes",
                        scene.solver.conjugateGradient ? "cg" : "jacobi",
                        steps ? double(c.pressureIterations - density0 + c.divergenceIterations - divergence0) / double(steps) : 0.0,
                        steps ? double(c.pressureIterations - density0) / double(steps) : 0.0,
                        steps ? double(c.divergenceIterations - divergence0) / double(steps) : 0.0, c.compressionPasses - passes0),
      sim.time() > time0 ? tSim / (sim.time() - time0) : 0.0) + [&] {
        std::string w;
        for (const auto& e : sim.effects()) {  // each effect's own counts (since this process started)
          std::string counts;
          for (const auto& [key, value] : e->statistics()) counts += fmt::format("{}{} {:g}", counts.empty() ? "" : "; ", key, value);
          if (!counts.empty()) w += fmt::format("  {}: {}\n", e->name(), counts);
        }
        for (const std::string& line : runWarnings(sim, seeded)) w += "  warning: " + line + "\n";
        return w;
      }();
}

std::string runSurfacing(const StageOptions& opt, const Scene& scene, const SurfacingSettings& settings, const fs::path& out,
                         const FrameRecords& records) {
  const int lastFrame = lastFrameToRun(opt, scene);
  const auto t0 = Clock::now();
  int done = 0, skipped = 0, missing = 0;
  size_t voxels = 0;
  for (int f = opt.firstFrame; f <= lastFrame; ++f) {
    const fs::path particles = particleFile(out, f);
    if (records.verify("surface", f)) {
      ++skipped;
      continue;
    }
    if (!awaitInput(opt, records, "particles", f, particles, "sim")) {
      ++missing;
      continue;
    }
    const auto f0 = Clock::now();
    discardFrame(records, "surface", f, {surfaceFile(out, f)});
    const auto r = surfacing::surfaceFrame(particles.string(), scene, settings, surfaceFile(out, f).string(), (out / "mesh").string(), f);
    std::vector<fs::path> written(r.written.begin(), r.written.end());
    records.write("surface", f, written);
    ++done;
    voxels += r.activeVoxels;
    const double elapsed = seconds(Clock::now() - t0);
    fmt::print(stderr, "[surface {:4d}/{}] {} phase(s), {} active voxels, {} interface voxels closed, {:.2f} s  elapsed {}  left ~{}\n",
               f, lastFrame, settings.phases.size(), r.activeVoxels, r.interfaceVoxels, seconds(Clock::now() - f0), formatDuration(elapsed),
               formatDuration(elapsed / (f - opt.firstFrame + 1) * (lastFrame - f)));
  }
  const double total = seconds(Clock::now() - t0);
  if (missing > 0) fmt::print(stderr, "surface: {} frame(s) have no finished particle file yet (run the sim stage)\n", missing);
  return fmt::format("  surface       {:>8.2f} s   {} frame(s) surfaced ({:.2f} s each, {:.0f} active voxels each), {} already done\n",
                     total, done, done > 0 ? total / done : 0.0, done > 0 ? double(voxels) / done : 0.0, skipped);
}

std::string runRender(const StageOptions& opt, const Scene& scene, const RenderSettings& settings, const fs::path& out,
                      const FrameRecords& records) {
  const int lastFrame = lastFrameToRun(opt, scene);
  const auto t0 = Clock::now();
  int done = 0, skipped = 0, missing = 0;
  uint64_t rays = 0;
  double traceSeconds = 0;
  if (!settings.cameraFraming.empty()) fmt::print(stderr, "render: {}\n", settings.cameraFraming);
  std::vector<int> unseen, empty;
  for (int f = opt.firstFrame; f <= lastFrame; ++f) {
    if (records.verify("render", f)) {
      ++skipped;
      continue;
    }
    if (!awaitInput(opt, records, "surface", f, surfaceFile(out, f), "surface")) {
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
    const fs::path exr = renderFile(out, f, "exr"), png = renderFile(out, f, "png");
    discardFrame(records, "render", f, {exr, png});
    const auto r = render::renderFrame(surfaceFile(out, f).string(), scene, settings, exr.string(), png.string(), f, progress);
    records.write("render", f, {exr, png});
    if (!r.anyFluid) empty.push_back(f);
    else if (r.fluidCoverage == 0) unseen.push_back(f);
    ++done;
    rays += r.rays;
    traceSeconds += r.seconds;
    const double elapsed = seconds(Clock::now() - t0);
    fmt::print(stderr, "[render  {:4d}/{}] {}x{} x {} spp, {} triangles, {:.2f} Mrays/s, {:.2f} s  elapsed {}  left ~{}\n", f,
               lastFrame, settings.width, settings.height, settings.samples, r.triangles,
               r.seconds > 0 ? r.rays / r.seconds / 1e6 : 0.0, seconds(Clock::now() - f0), formatDuration(elapsed),
               formatDuration(elapsed / (f - opt.firstFrame + 1) * (lastFrame - f)));
  }
  const double total = seconds(Clock::now() - t0);
  if (missing > 0) fmt::print(stderr, "render: {} frame(s) have no finished surface file yet (run the surface stage)\n", missing);
  auto list = [](const std::vector<int>& v) {
    std::string s;
    for (size_t k = 0; k < v.size() && k < 10; ++k) s += (k ? ", " : "") + std::to_string(v[k]);
    return v.size() > 10 ? s + fmt::format(" and {} more", v.size() - 10) : s;
  };
  if (!empty.empty()) fmt::print(stderr, "warning: {} frame(s) have no fluid surface to render (frames {})\n", empty.size(), list(empty));
  if (!unseen.empty())
    fmt::print(stderr, "warning: the camera sees no fluid in {} frame(s) (frames {}): check render.camera_position and look_at, or render.camera_key\n",
               unseen.size(), list(unseen));
  return fmt::format("  render        {:>8.2f} s   {} frame(s) rendered ({:.2f} s each, {:.2f} Mrays/s), {} already done\n", total,
                     done, done > 0 ? total / done : 0.0, traceSeconds > 0 ? rays / traceSeconds / 1e6 : 0.0, skipped);
}

std::string runPreview(const StageOptions& opt, const Scene& scene, const RenderSettings& settings, const fs::path& out,
                       const FrameRecords& records) {
  const int lastFrame = lastFrameToRun(opt, scene);
  const auto t0 = Clock::now();
  int done = 0, skipped = 0;
  for (int f = opt.firstFrame; f <= lastFrame; ++f) {
    if (records.verify("preview", f)) {
      ++skipped;
      continue;
    }
    if (!awaitInput(opt, records, "particles", f, particleFile(out, f), "sim")) continue;
    discardFrame(records, "preview", f, {previewFile(out, f)});
    const auto r = render::renderPreview(particleFile(out, f).string(), scene, settings, previewFile(out, f).string(), opt.previewColour);
    records.write("preview", f, {previewFile(out, f)});
    ++done;
    if (seconds(Clock::now() - t0) > 2 || f == lastFrame)
      fmt::print(stderr, "[preview {:4d}/{}] {} particles, {:.2f} s\n", f, lastFrame, r.particles, r.seconds);
  }
  const double total = seconds(Clock::now() - t0);
  return fmt::format("  preview       {:>8.2f} s   {} frame(s) drawn, {} already done\n", total, done, skipped);
}

/// H.264 (yuv420p, even sizes) of the rendered frames, or of the previews if nothing is rendered.
/// Only frames whose records verify are used: the movie never shows a damaged or partial frame.
std::string runEncode(const StageOptions& opt, const Scene& scene, const fs::path& out, const FrameRecords& records) {
  const int lastFrame = lastFrameToRun(opt, scene);
  const auto t0 = Clock::now();
  struct Source {
    const char* kind;
    const char* stage;
    const char* pattern;
  };
  const Source sources[] = {{"rendered", "render", "render/render.%04d.png"}, {"preview", "preview", "preview/preview.%04d.png"}};
  const Source* used = nullptr;
  int first = -1, count = 0;
  for (const Source& src : sources) {
    first = -1, count = 0;
    for (int f = opt.firstFrame; f <= lastFrame; ++f) {
      if (!records.verify(src.stage, f)) {
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
  if (count == 0) return "  encode            -      no finished rendered or preview frames to encode\n";
  if (findOnPath("ffmpeg").empty())
    throw std::runtime_error("encode: ffmpeg was not found on PATH (Debian: apt-get install ffmpeg; scripts/setup.sh installs it)");
  // ffmpeg runs in the run folder with relative names and an argument vector: neither the scene
  // name nor --out passes through a shell or ffmpeg's pattern syntax.
  const std::string movie = scene.name + ".mp4", tmp = scene.name + ".tmp.mp4";
  const fs::path log = out / "encode.log";
  const std::vector<std::string> argv = {
      "ffmpeg", "-nostdin", "-y", "-loglevel", "error", "-framerate", fmt::format("{}", scene.frameRate), "-start_number",
      std::to_string(first), "-i", used->pattern, "-frames:v", std::to_string(count), "-c:v", "libx264", "-preset", "medium",
      "-crf", "18", "-pix_fmt", "yuv420p", "-vf", "scale=trunc(iw/2)*2:trunc(ih/2)*2", "-fflags", "+bitexact", "-flags:v",
      "+bitexact", "-map_metadata", "-1", tmp};
  const int status = runProgram(argv, {out.string(), "", log.string()});
  std::error_code ec;
  if (status != 0 || fs::file_size(out / tmp, ec) == 0) {
    fs::remove(out / tmp, ec);
    std::ifstream in(log);
    const std::string message((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    throw std::runtime_error(fmt::format("encode: ffmpeg exited with status {} writing {}: {}", status, (out / movie).string(), message));
  }
  fs::remove(log, ec);
  fs::rename(out / tmp, out / movie);
  const double total = seconds(Clock::now() - t0);
  fmt::print(stderr, "[encode] {} {} frames from {} -> {}\n", count, used->kind, first, (out / movie).string());
  return fmt::format("  encode        {:>8.2f} s   {} {} frame(s) -> {}\n", total, count, used->kind, (out / movie).string());
}

/// What is really in the folder now, by verified records, over the frames asked for.
std::string framesPresent(const StageOptions& opt, const Scene& scene, const FrameRecords& records, std::string& warnings) {
  const int lastFrame = lastFrameToRun(opt, scene);
  const int wanted = lastFrame - opt.firstFrame + 1;
  std::string line = "  frames present:";
  struct Stage {
    const char* name;
    bool ran;
  };
  for (const Stage& s : {Stage{"particles", opt.sim}, Stage{"surface", opt.surface}, Stage{"render", opt.render},
                         Stage{"preview", opt.preview}}) {
    int n = 0;
    for (int f = opt.firstFrame; f <= lastFrame; ++f) n += records.verify(s.name, f) ? 1 : 0;
    if (s.ran || n > 0) line += fmt::format(" {} {}/{}", s.name, n, wanted);
    if (s.ran && n < wanted) warnings += fmt::format("  warning: only {} of {} {} frames are finished\n", n, wanted, s.name);
  }
  return line + "\n";
}

}  // namespace

int runStages(const SceneStages& stages, const StageOptions& opt, const fs::path& out) {
  const Scene& scene = stages.scene;
  fs::create_directories(out);
  const int last = lastFrameToRun(opt, scene);
  std::vector<LockScope> scopes;
  if (opt.sim) scopes.push_back({"sim"});
  for (const auto& [ran, stage] : {std::pair{opt.surface, "surface"}, {opt.render, "render"}, {opt.preview, "preview"}})
    if (ran) scopes.push_back({stage, opt.firstFrame, last});
  if (opt.encode) scopes.push_back({"encode"});
  const FolderLocks locks(out, scopes);
  if (const int n = removeStaleTemporaries(out, locks); n > 0)
    fmt::print(stderr, "removed {} temporary file(s) an interrupted run left in {}\n", n, out.string());
  const FrameRecords records(out);
  std::string summary;
  if (opt.sim) summary += runSimulation(opt, scene, out, records);
  else writeSceneCopy(scene, out);
  if (summary.empty()) summary = fmt::format("\nsummary for {}\n", scene.name);
  if (opt.surface) summary += runSurfacing(opt, scene, stages.surfacing, out, records);
  if (opt.render) summary += runRender(opt, scene, stages.render, out, records);
  if (opt.preview) summary += runPreview(opt, scene, stages.render, out, records);
  if (opt.encode) summary += runEncode(opt, scene, out, records);
  std::string warnings;
  summary += framesPresent(opt, scene, records, warnings) + warnings;
  fmt::print(stderr, "{}", summary);
  std::ofstream log(out / "run.log", std::ios::app);
  log << summary;
  log.close();
  if (!log) throw std::runtime_error("cannot append to " + (out / "run.log").string());
  return 0;
}

}  // namespace mf::pipeline
