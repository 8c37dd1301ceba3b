// multifluid: runs scenes frame by frame through the stages sim -> surface -> render -> encode
// (and a quick particle preview), each also a subcommand on a frame range; `diff` compares two
// frame sequences; `report` measures accuracy and stability. The command line is parsed by CLI11:
// numbers are strict, ranges are checked (frames against the scene), and a usage error exits 2.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "pipeline/export_blender.h"
#include "pipeline/farm.h"
#include "pipeline/report.h"
#include "pipeline/scene_stages.h"
#include "pipeline/stages.h"
#include "render/image.h"
#include "sim/scene_budget.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace fs = std::filesystem;

namespace {

constexpr const char* kDefaultScene = "lava_lamp";
// With no argument at all, the default scene runs at demo quality: about ten minutes on 2 cores
// from nothing to an mp4 (the scene file itself asks for 60 s at 10 fps and 16 samples).
const std::vector<std::string> kDefaultDemoSettings = {"scene.end_time=12.0", "scene.frame_rate=5.0", "render.samples=8"};

/// A usage error: printed with the command's help hint, exit status 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Options {
  std::string command = "run";
  std::string scene, out;
  std::vector<std::string> sets;
  std::string frames, stages, resolution, previewColour = "phase";
  int samples = 0;
  int threads = 0;
  double maxMemoryMiB = 0;
  double maxStepsPerFrame = 1e5;
  bool force = false;
  double waitForInput = 0;
  // farm
  std::string farmDir, partition, timeLimit, farmStages = "sim,surface,render,encode";
  int framesPerTask = 1, cpusPerTask = 1;
  bool dryRun = false;
  // diff
  std::vector<std::string> diffPaths;
  double threshold = 0.016, failPercent = 1;
  std::string diffFormat = "exr";
  bool onlyCommon = false;
  // export
  mf::pipeline::BlenderExportOptions blender;
};

/// Only decimal digits, at most `maxDigits` of them (so that stoi cannot overflow).
bool isCount(const std::string& t, size_t maxDigits) {
  return !t.empty() && t.size() <= maxDigits && t.find_first_not_of("0123456789") == std::string::npos;
}

/// "A-B" or "A" with 0 <= A <= B: CLI11 validator (strict: "2-3x" is refused).
std::string checkFrames(const std::string& s) {
  const size_t dash = s.find('-');
  auto digits = [](const std::string& t) { return isCount(t, 7); };
  const std::string a = s.substr(0, dash), b = dash == std::string::npos ? a : s.substr(dash + 1);
  if (!digits(a) || !digits(b)) return "takes A-B or A (frame numbers, 0 <= A <= B), e.g. 0-30";
  if (std::stoi(a) > std::stoi(b)) return "takes A-B with A <= B";
  return "";
}

std::string checkResolution(const std::string& s) {
  const size_t x = s.find('x');
  auto digits = [](const std::string& t) { return isCount(t, 5); };
  if (x == std::string::npos || !digits(s.substr(0, x)) || !digits(s.substr(x + 1)))
    return "takes WxH, e.g. 320x180";
  const int w = std::stoi(s.substr(0, x)), h = std::stoi(s.substr(x + 1));
  if (w < 8 || h < 8 || w > 16384 || h > 16384) return "each of W and H must be in [8, 16384]";
  return "";
}

std::string checkStages(const std::string& s) {
  if (s.empty()) return "needs at least one stage (sim, surface, render, preview, encode)";
  std::stringstream ss(s);
  for (std::string stage; std::getline(ss, stage, ',');)
    if (stage != "sim" && stage != "surface" && stage != "render" && stage != "preview" && stage != "encode")
      return "unknown stage '" + stage + "' (stages: sim, surface, render, preview, encode)";
  if (s.back() == ',') return "has an empty stage name";
  return "";
}

void addSceneOptions(CLI::App& app, Options& opt, bool stageOptions) {
  app.add_option("SCENE", opt.scene,
                 "a scene file (a path with '/' or a name ending in .toml) or the name of an embedded scene")
      ->required();
  app.add_option("--set", opt.sets, "key=value: override any scene key (TOML value), e.g. solver.cfl=0.3")->take_all();
  app.add_option("--max-memory", opt.maxMemoryMiB, "refuse scenes estimated above this many MiB (default: 80 % of the machine's memory)")
      ->check(CLI::Range(1.0, 1e9));
  app.add_option("--max-steps-per-frame", opt.maxStepsPerFrame,
                 "refuse scenes estimated above, and stop runs reaching, this many steps per frame (0: no bound)")
      ->check(CLI::Range(0.0, 1e12));
  app.add_flag("--force", opt.force, "run a scene over the step estimate anyway (the run still stops at the bound)");
  if (!stageOptions) return;
  app.add_option("--out", opt.out, "the run folder (default runs/<scene name>)");
  app.add_option("--frames", opt.frames, "A-B or A: the frames to run (within the scene's)")->check(CLI::Validator(checkFrames, "A-B"));
  app.add_option("--threads", opt.threads, "worker threads (default: all cores)")->check(CLI::Range(1, 4096));
  app.add_option("--resolution", opt.resolution, "WxH of rendered frames, e.g. 320x180")->check(CLI::Validator(checkResolution, "WxH"));
  app.add_option("--samples", opt.samples, "samples per pixel")->check(CLI::Range(1, 100000));
  app.add_option("--preview-colour,--preview-color", opt.previewColour, "preview colours")
      ->check(CLI::IsMember({"phase", "temperature"}));
  app.add_option("--wait-for-input", opt.waitForInput,
                 "seconds to wait for an input frame another process is still making (farm tasks; default 0: skip it)")
      ->check(CLI::Range(0.0, 1e7));
}

std::string checkFarmStages(const std::string& s) {
  if (s.empty()) return "needs at least one stage (sim, surface, render, encode)";
  std::stringstream ss(s);
  for (std::string stage; std::getline(ss, stage, ',');)
    if (stage != "sim" && stage != "surface" && stage != "render" && stage != "encode")
      return "unknown stage '" + stage + "' (farm stages: sim, surface, render, encode)";
  if (s.back() == ',') return "has an empty stage name";
  return "";
}

void addFarmCommands(CLI::App& app, Options& opt) {
  CLI::App* farm = app.add_subcommand("farm", "run a scene on a Slurm farm: submit, status, cancel (the run folder must be on shared storage)");
  farm->require_subcommand(1);
  CLI::App* submit = farm->add_subcommand("submit", "write sbatch scripts into DIR/farm and submit the stages as chained jobs");
  addSceneOptions(*submit, opt, false);
  submit->add_option("--out", opt.out, "the run folder, on storage every node shares")->required();
  submit->add_option("--frames", opt.frames, "A-B or A: the frames to run (within the scene's)")->check(CLI::Validator(checkFrames, "A-B"));
  submit->add_option("--frames-per-task", opt.framesPerTask, "frames per surfacing or rendering task (default 1)")->check(CLI::Range(1, 100000));
  submit->add_option("--cpus-per-task", opt.cpusPerTask, "CPUs (threads) of each job and task (default 1)")->check(CLI::Range(1, 4096));
  submit->add_option("--partition", opt.partition, "the Slurm partition (default: the cluster's)");
  submit->add_option("--time", opt.timeLimit, "each job's time limit (Slurm: M, M:S, H:M:S, D-H, D-H:M, D-H:M:S)");
  submit->add_option("--wait-for-input", opt.waitForInput, "seconds a task waits for its input frame before it requeues itself to free its CPUs (default 300)")
      ->check(CLI::Range(1.0, 1e7));
  submit->add_option("--stages", opt.farmStages, "comma-separated: sim, surface, render, encode (default all)")
      ->check(CLI::Validator(checkFarmStages, "LIST"));
  submit->add_option("--resolution", opt.resolution, "WxH of rendered frames, e.g. 320x180")->check(CLI::Validator(checkResolution, "WxH"));
  submit->add_option("--samples", opt.samples, "samples per pixel")->check(CLI::Range(1, 100000));
  submit->add_flag("--dry-run", opt.dryRun, "write the scripts and print the sbatch command lines; submit nothing");
  submit->callback([&opt] { opt.command = "farm submit"; });
  for (const char* name : {"status", "cancel"}) {
    CLI::App* sub = farm->add_subcommand(name, std::string(name) == "status" ? "frames done per stage, the jobs' states, failed tasks' errors"
                                                                              : "scancel the run's jobs");
    sub->add_option("DIR", opt.farmDir, "the run folder given to farm submit --out")->required();
    sub->callback([&opt, name] { opt.command = std::string("farm ") + name; });
  }
}

/// The scene with every stage's settings (the command line's render settings applied), and its
/// budget checked.
mf::SceneStages loadCheckedScene(const Options& opt, mf::SceneBudget* budgetOut = nullptr) {
  std::vector<std::string> sets = opt.sets;
  if (!opt.resolution.empty()) {
    const size_t x = opt.resolution.find('x');
    sets.push_back("render.width=" + opt.resolution.substr(0, x));
    sets.push_back("render.height=" + opt.resolution.substr(x + 1));
  }
  if (opt.samples > 0) sets.push_back(fmt::format("render.samples={}", opt.samples));
  mf::SceneStages stages = mf::loadSceneStages(opt.scene, sets);
  mf::BudgetLimits limits;
  if (opt.maxMemoryMiB > 0) limits.maxMemoryBytes = opt.maxMemoryMiB * 1024 * 1024;
  limits.maxStepsPerFrame = opt.maxStepsPerFrame;
  limits.force = opt.force;
  const mf::SceneBudget budget = mf::checkSceneBudget(stages.scene, limits, stages.laterSizes());
  if (budgetOut) *budgetOut = budget;
  return stages;
}

int runStagesCommand(const Options& opt) {
  const mf::SceneStages stages = loadCheckedScene(opt);
  const mf::Scene& scene = stages.scene;
  mf::pipeline::StageOptions so;
  so.threads = opt.threads;
  so.maxStepsPerFrame = opt.maxStepsPerFrame;
  so.waitForInputSeconds = opt.waitForInput;
  so.previewColour = opt.previewColour == "temperature" ? mf::render::PreviewColour::Temperature : mf::render::PreviewColour::Phase;
  if (!opt.frames.empty()) {
    const size_t dash = opt.frames.find('-');
    so.firstFrame = std::stoi(opt.frames.substr(0, dash));
    so.lastFrame = dash == std::string::npos ? so.firstFrame : std::stoi(opt.frames.substr(dash + 1));
    if (so.lastFrame > scene.lastFrame())
      throw UsageError(fmt::format("--frames {}: the scene '{}' has frames 0-{} ({} s at {} frames/s)", opt.frames, scene.name,
                                   scene.lastFrame(), scene.endTime, scene.frameRate));
  }
  if (opt.command != "run") {
    so.sim = opt.command == "sim", so.surface = opt.command == "surface", so.render = opt.command == "render";
    so.preview = opt.command == "preview", so.encode = opt.command == "encode";
  }
  if (!opt.stages.empty()) {
    so.sim = so.surface = so.render = so.preview = so.encode = false;
    std::stringstream ss(opt.stages);
    for (std::string s; std::getline(ss, s, ',');) {
      so.sim |= s == "sim", so.surface |= s == "surface", so.render |= s == "render";
      so.preview |= s == "preview", so.encode |= s == "encode";
    }
  }
  // The scene name was checked when the file was read (letters, digits, '_', '-', '.'; no '/'
  // or '..'), so the default folder stays inside runs/.
  const fs::path out = opt.out.empty() ? fs::path("runs") / scene.name : fs::path(opt.out);
  std::unique_ptr<tbb::global_control> threads;
  if (opt.threads > 0) threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, opt.threads);
  return mf::pipeline::runStages(stages, so, out);
}

int farmSubmitCommand(Options opt) {
  if (opt.waitForInput <= 0) opt.waitForInput = 300;
  for (const char c : opt.out)
    if (c == '%' || c == '\\' || static_cast<unsigned char>(c) < 0x20)
      throw UsageError("--out " + opt.out + ": a farm run folder may not contain '%', '\\' or control characters (Slurm reads "
                       "them as file name patterns in its log paths)");
  if (!opt.partition.empty() &&
      (opt.partition.size() > 64 || opt.partition.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") !=
                                        std::string::npos))
    throw UsageError("--partition " + opt.partition + ": takes a partition name (letters, digits, '_', '.', '-'; at most 64)");
  mf::pipeline::FarmSubmitOptions fo;
  if (!opt.timeLimit.empty()) {
    fo.timeLimitSeconds = mf::pipeline::parseSlurmTime(opt.timeLimit);
    if (fo.timeLimitSeconds <= 0)
      throw UsageError("--time " + opt.timeLimit + ": takes M, M:S, H:M:S, D-H, D-H:M or D-H:M:S (more than 0 s), e.g. 2:00:00");
  }
  const mf::Scene scene = loadCheckedScene(opt).scene;
  fo.firstFrame = 0, fo.lastFrame = scene.lastFrame();
  if (!opt.frames.empty()) {
    const size_t dash = opt.frames.find('-');
    fo.firstFrame = std::stoi(opt.frames.substr(0, dash));
    fo.lastFrame = dash == std::string::npos ? fo.firstFrame : std::stoi(opt.frames.substr(dash + 1));
    if (fo.lastFrame > scene.lastFrame())
      throw UsageError(fmt::format("--frames {}: the scene '{}' has frames 0-{} ({} s at {} frames/s)", opt.frames, scene.name,
                                   scene.lastFrame(), scene.endTime, scene.frameRate));
  }
  fo.out = fs::absolute(opt.out).lexically_normal();
  fo.stages.clear();
  std::stringstream ss(opt.farmStages);
  for (std::string st; std::getline(ss, st, ',');) fo.stages.push_back(st);
  fo.framesPerTask = opt.framesPerTask;
  fo.cpusPerTask = opt.cpusPerTask;
  fo.waitForInputSeconds = opt.waitForInput;
  fo.partition = opt.partition;
  fo.timeLimit = opt.timeLimit;
  fo.dryRun = opt.dryRun;
  fo.passOptions = {"--max-steps-per-frame", fmt::format("{}", opt.maxStepsPerFrame)};
  if (opt.maxMemoryMiB > 0) fo.passOptions.insert(fo.passOptions.end(), {"--max-memory", fmt::format("{}", opt.maxMemoryMiB)});
  if (opt.force) fo.passOptions.push_back("--force");
  return mf::pipeline::farmSubmit(scene, fo);
}

int validate(const Options& opt) {
  mf::SceneBudget b;
  const mf::Scene scene = loadCheckedScene(opt, &b).scene;
  fmt::print("{}: valid scene '{}', {} phase(s), {} solid(s), {} fluid block(s), effects:", scene.sourceFile, scene.name,
             scene.phases.size(), scene.solids.size(), scene.fluids.size());
  for (const auto& e : scene.effects) fmt::print(" {}", e.name);
  fmt::print("\n  estimate: {:.0f} particles, {:.0f} boundary samples, {:.0f} MiB at most; dt {:.3g} s at rest, set by {}; {:.0f} steps per frame\n",
             b.particles, b.boundarySamples, b.memoryBytes / (1024.0 * 1024.0), b.restTimeStep, b.timeStepLimiter, b.stepsPerFrame);
  return 0;
}

/// Compares the images of two frame sequences by name (or two image files). A run folder stands
/// for its render/ folder; only one format is compared (EXR by default: the linear values).
int diffSequences(const Options& opt) {
  std::string dirA = opt.diffPaths.at(0), dirB = opt.diffPaths.at(1);
  std::vector<std::pair<fs::path, fs::path>> pairs;
  std::vector<std::string> missing;
  const std::string ext = "." + opt.diffFormat;
  auto isImage = [&](const fs::path& p) { return p.extension() == ext; };
  if (fs::is_regular_file(dirA) && fs::is_regular_file(dirB)) {
    pairs.push_back({dirA, dirB});
  } else {
    for (std::string* dir : {&dirA, &dirB}) {
      if (!fs::is_directory(*dir)) throw UsageError("diff: " + *dir + " is not a directory or an image file");
      if (fs::is_directory(fs::path(*dir) / "render") && fs::exists(fs::path(*dir) / "records")) {
        fmt::print("{}: a run folder; comparing its render/ frames\n", *dir);
        *dir = (fs::path(*dir) / "render").string();
      }
    }
    std::vector<fs::path> names;
    for (const auto& e : fs::directory_iterator(dirA))
      if (isImage(e.path())) names.push_back(e.path().filename());
    for (const auto& e : fs::directory_iterator(dirB))
      if (isImage(e.path()) && !fs::exists(fs::path(dirA) / e.path().filename()))
        missing.push_back(e.path().filename().string() + " (only in " + dirB + ")");
    std::sort(names.begin(), names.end());
    for (const auto& n : names) {
      if (fs::exists(fs::path(dirB) / n)) pairs.push_back({fs::path(dirA) / n, fs::path(dirB) / n});
      else missing.push_back(n.string() + " (only in " + dirA + ")");
    }
    std::sort(missing.begin(), missing.end());
    if (pairs.empty())
      fmt::print("no {} frame is in both {} and {} (--format exr|png picks the format)\n", opt.diffFormat, dirA, dirB);
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
  for (const auto& m : missing) fmt::print("{}: {}\n", opt.onlyCommon ? "skipped" : "missing", m);
  fmt::print("{} frame(s) compared, {} failed, {} {} (threshold {}, fail above {}% of pixels){}\n", pairs.size(), failed,
             missing.size(), opt.onlyCommon ? "on one side only, skipped" : "missing", opt.threshold, opt.failPercent,
             failed > 0 ? fmt::format("; difference images in {}", diffDir.string()) : "");
  return failed > 0 || (!missing.empty() && !opt.onlyCommon) || pairs.empty() ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && args[0] == "report") {
    try {
      return mf::report::runReportCommand(std::vector<std::string>(args.begin() + 1, args.end()));
    } catch (const std::exception& e) {
      fmt::print(stderr, "multifluid report: {}\n", e.what());
      return 1;
    }
  }
  Options opt;
  if (args.empty()) {
    // No argument at all: the demo (see kDefaultDemoSettings).
    args = {"run", kDefaultScene};
    opt.sets = kDefaultDemoSettings;
  }
  const std::vector<std::string> commands = {"run",  "sim",      "surface", "render", "preview", "encode",
                                             "diff", "validate", "scenes",  "farm",   "export"};
  const bool help = args[0] == "-h" || args[0] == "--help";
  if (!help && std::find(commands.begin(), commands.end(), args[0]) == commands.end()) args.insert(args.begin(), "run");

  CLI::App app{fmt::format("multifluid: multi-fluid SPH (Müller et al. 2005) -> OpenVDB level sets -> Embree path tracer.\n"
                           "With no argument at all, the embedded '{}' scene runs into runs/{} at demo quality ({}).\n"
                           "A re-run with the same scene and --out resumes from the last checkpoint; finished frames of every\n"
                           "stage (those whose completion record in DIR/records verifies) are skipped.",
                           kDefaultScene, kDefaultScene, fmt::join(kDefaultDemoSettings, ", ")),
               "multifluid"};
  app.require_subcommand(1);
  app.footer("Reports: multifluid report accuracy|stability|all [--quick] [--out DIR] (see multifluid report --help)");
  for (const char* name : {"run", "sim", "surface", "render", "preview", "encode"}) {
    const std::string what = std::string(name) == "run" ? "run the stages sim, surface, render, encode (or --stages LIST)"
                                                        : std::string("run the ") + name + " stage alone";
    CLI::App* sub = app.add_subcommand(name, what);
    addSceneOptions(*sub, opt, true);
    if (std::string(name) == "run")
      sub->add_option("--stages", opt.stages, "comma-separated: sim, surface, render, preview, encode")
          ->check(CLI::Validator(checkStages, "LIST"));
    sub->callback([&opt, name] { opt.command = name; });
  }
  CLI::App* validateCmd = app.add_subcommand("validate", "check a scene and print its estimates");
  addSceneOptions(*validateCmd, opt, false);
  validateCmd->callback([&opt] { opt.command = "validate"; });
  CLI::App* diff = app.add_subcommand("diff", "compare two frame sequences (folders of PNG/EXR) or two images");
  diff->add_option("A B", opt.diffPaths, "two run folders, two frame folders (e.g. runs/x/render) or two image files")->required()->expected(2);
  diff->add_option("--threshold", opt.threshold, "a pixel fails when a displayed channel differs by more than this")
      ->check(CLI::Range(0.0, 1.0));
  diff->add_option("--fail-percent", opt.failPercent, "a frame fails when more than this % of its pixels fail")
      ->check(CLI::Range(0.0, 100.0));
  diff->add_option("--out", opt.out, "where difference images go (default diff/)");
  diff->add_option("--format", opt.diffFormat, "which frames of two folders to compare (default exr)")->check(CLI::IsMember({"exr", "png"}));
  diff->add_flag("--only-common", opt.onlyCommon, "frames on one side only are listed, not failed");
  diff->callback([&opt] { opt.command = "diff"; });
  app.add_subcommand("scenes", "list the embedded scenes")->callback([&opt] { opt.command = "scenes"; });
  addFarmCommands(app, opt);
  CLI::App* exportCmd = app.add_subcommand("export", "hand a run to a DCC tool: export blender DIR");
  exportCmd->require_subcommand(1);
  CLI::App* blender = exportCmd->add_subcommand("blender", "build a .blend of a run folder with Blender in background mode");
  blender->add_option("DIR", opt.blender.runDir, "the run folder (it needs finished surface frames)")->required();
  blender->add_option("--out", opt.blender.out, "the .blend to write (default DIR/<scene>.blend)");
  blender->add_option("--meshes", opt.blender.meshes, "vdb: the level sets with Volume to Mesh (default); ply: the run's PLY meshes")
      ->check(CLI::IsMember({"vdb", "ply"}));
  blender->add_option("--timeout", opt.blender.timeoutSeconds, "seconds before Blender is stopped (default 1800)")->check(CLI::Range(1.0, 1e6));
  blender->callback([&opt] { opt.command = "export blender"; });

  std::vector<const char*> cargv = {"multifluid"};
  for (const auto& a : args) cargv.push_back(a.c_str());
  try {
    app.parse(int(cargv.size()), const_cast<char**>(cargv.data()));
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "multifluid: {}\nRun 'multifluid --help' (or 'multifluid COMMAND --help') for usage.\n", e.what());
    return 2;
  }

  try {
    if (opt.command == "scenes") {
      for (const auto& n : mf::embeddedSceneNames()) fmt::print("{}\n", n);
      return 0;
    }
    if (opt.command == "validate") return validate(opt);
    if (opt.command == "diff") return diffSequences(opt);
    if (opt.command == "farm submit") return farmSubmitCommand(opt);
    if (opt.command == "farm status") return mf::pipeline::farmStatus(opt.farmDir);
    if (opt.command == "farm cancel") return mf::pipeline::farmCancel(opt.farmDir);
    if (opt.command == "export blender") return mf::pipeline::exportBlender(opt.blender);
    return runStagesCommand(opt);
  } catch (const UsageError& e) {
    fmt::print(stderr, "multifluid: {}\n", e.what());
    return 2;
  } catch (const mf::SceneError& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 2;
  } catch (const mf::pipeline::InputNotReady& e) {
    fmt::print(stderr, "multifluid: {}\n", e.what());
    return 75;
  } catch (const mf::pipeline::StopRequested& e) {
    fmt::print(stderr, "multifluid: {}\n", e.what());
    return 128 + e.signal;
  } catch (const mf::NumericalInstability& e) {
    fmt::print(stderr, "multifluid: {}\nNo frame was written for the failed step; the last checkpoint is intact.\n", e.what());
    return 3;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "multifluid: out of memory (the scene's estimate passed; lower --max-memory or the scene's resolution)\n");
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "multifluid: {}\n", e.what());
    return 1;
  }
}
