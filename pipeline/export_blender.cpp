#include "pipeline/export_blender.h"

#include <unistd.h>

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "pipeline/process.h"
#include "pipeline/run_folder.h"
#include "pipeline/scene_stages.h"
#include "render/camera.h"
#include "render/geometry.h"
#include "sim/file_util.h"

#ifndef MULTIFLUID_BLENDER_SCRIPT
#define MULTIFLUID_BLENDER_SCRIPT ""
#endif

namespace fs = std::filesystem;

namespace mf::pipeline {

namespace {

/// A JSON string: quotes, backslashes and control characters escaped (paths may hold anything).
std::string str(const std::string& s) {
  std::string o = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') o += '\\', o += c;
    else if (static_cast<unsigned char>(c) < 0x20) o += fmt::format("\\u{:04x}", int(c));
    else o += c;
  }
  return o + "\"";
}
std::string num(double v) {
  if (!std::isfinite(v)) throw std::runtime_error("export: a non-finite number in the scene's render settings");
  return fmt::format("{:.9g}", v);
}
std::string vec(const Vec3& v) { return "[" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "]"; }

/// An emission or absorption ramp: the grid it reads (surfacing's <attribute>_<fluid>), its range
/// and colours.
std::string rampJson(const ColourRamp& ramp, const std::string& fluid) {
  if (fluid.empty() || ramp.empty()) return "null";
  std::string colours;
  for (const Vec3& c : ramp.colours) colours += (colours.empty() ? "" : ", ") + vec(c);
  return fmt::format(R"({{"grid": {}, "range": [{}, {}], "colours": [{}]}})", str(ramp.attribute + "_" + fluid), num(ramp.lo),
                     num(ramp.hi), colours);
}

std::string material(const MaterialSpec& m, const std::string& fluid = "") {
  const char* kind = m.kind == MaterialSpec::Kind::Dielectric ? "dielectric"
                     : m.kind == MaterialSpec::Kind::Medium   ? "medium"
                     : m.kind == MaterialSpec::Kind::Diffuse  ? "diffuse"
                                                              : "emitter";
  return fmt::format(R"({{"kind": {}, "ior": {}, "absorption": {}, "scattering": {}, "colour": {}, "emission": {}, "priority": {}, "visible": {}, "emission_ramp": {}, "absorption_ramp": {}}})",
                     str(kind), num(m.ior), vec(m.absorption), num(m.scattering), vec(m.colour), vec(m.emission), m.priority,
                     m.visible ? "true" : "false", rampJson(m.emissionRamp, fluid), rampJson(m.absorptionRamp, fluid));
}

/// The container's wall as the renderer traces it (render::solidMesh), in scene coordinates.
std::string containerMesh(const SolidSpec& s, const MaterialSpec& m) {
  const render::RenderMesh mesh = render::solidMesh(s, m.thickness, 64);
  std::string v, t;
  for (const auto& p : mesh.positions) v += fmt::format("{}{:.7g}, {:.7g}, {:.7g}", v.empty() ? "" : ", ", p.x, p.y, p.z);
  for (const auto& tri : mesh.triangles) t += fmt::format("{}{}, {}, {}", t.empty() ? "" : ", ", tri[0], tri[1], tri[2]);
  return fmt::format(R"({{"name": {}, "material": {}, "vertices": [{}], "triangles": [{}]}})", str(s.name), material(m), v, t);
}

std::string tail(const fs::path& file, size_t bytes) {
  std::ifstream in(file, std::ios::binary);
  std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return s.size() > bytes ? "..." + s.substr(s.size() - bytes) : s;
}

}  // namespace

std::string blenderScriptPath() {
  // The project has no install rules: the script stays in the source tree the binary was built from.
  const fs::path source = MULTIFLUID_BLENDER_SCRIPT;
  std::error_code ec;
  if (!source.empty() && fs::is_regular_file(source, ec)) return source.string();
  throw std::runtime_error("export: the Blender script " + source.string() +
                           " (in the source tree this program was built from) is missing");
}

int exportBlender(const BlenderExportOptions& opt) {
  const fs::path dir = fs::absolute(opt.runDir).lexically_normal();
  if (!fs::is_directory(dir / "records") || !fs::is_regular_file(dir / "scene.toml"))
    throw std::runtime_error(fmt::format("export: {} is not a run folder (no scene.toml and records/); make one with "
                                         "'multifluid run SCENE --out {}'",
                                         opt.runDir, opt.runDir));
  if (findOnPath("blender").empty())
    throw std::runtime_error("export: blender was not found on PATH; install it with 'scripts/setup.sh --with-blender' (Debian: "
                             "apt-get install blender)");
  const std::string script = blenderScriptPath();
  // The scene as run: its copy in the folder, with the overrides of that run already applied.
  const SceneStages stages = loadSceneStages((dir / "scene.toml").string());
  const Scene& scene = stages.scene;
  const RenderSettings& rs = stages.render;

  // The first unbroken run of finished surface frames (like the movie), checked by their records.
  const FrameRecords records(dir);
  int first = -1, last = -1;
  for (int f = 0; f <= scene.lastFrame(); ++f) {
    if (!records.verify("surface", f)) {
      if (first >= 0) break;
      continue;
    }
    if (first < 0) first = f;
    last = f;
  }
  if (first < 0)
    throw std::runtime_error(fmt::format("export: {} has no finished surface frames; run the surface stage first ('multifluid "
                                         "surface {} --out {}')",
                                         opt.runDir, (dir / "scene.toml").string(), opt.runDir));
  auto surfaceFile = [&](int f) { return dir / "surface" / fmt::format("surface.{:04d}.vdb", f); };
  auto meshFile = [&](const std::string& phase, int f) { return dir / "mesh" / fmt::format("{}.{:04d}.ply", phase, f); };
  if (opt.meshes == "ply") {
    if (!stages.surfacing.meshPly)
      throw std::runtime_error(fmt::format("export --meshes ply: the run wrote no PLY meshes (surfacing.meshes has no \"ply\"); "
                                           "export the level sets (--meshes vdb), or delete {}/records/surface.* and run: multifluid "
                                           "surface {}/scene.toml --out {} --set 'surfacing.meshes=[\"ply\"]'",
                                           opt.runDir, opt.runDir, opt.runDir));
  }

  if (rs.shutter > 0 && opt.meshes != "ply")
    fmt::print(stderr,
               "export: note: render.shutter is {}, but Blender blurs only meshes that carry velocities: export with --meshes ply "
               "for motion blur (the level sets' Volume to Mesh has none)\n",
               rs.shutter);
  const fs::path out = opt.out.empty() ? dir / (scene.name + ".blend") : fs::absolute(opt.out).lexically_normal();
  if (out.extension() != ".blend") throw std::runtime_error("export: --out " + out.string() + " must end in .blend");
  fs::create_directories(out.parent_path());

  std::string fluids;
  for (const uint16_t p : rs.phases) {
    const std::string& name = scene.phases[p].name;
    std::string meshes;
    if (opt.meshes == "ply")
      for (int f = first; f <= last; ++f) meshes += (meshes.empty() ? "" : ", ") + str(meshFile(name, f).string());
    fluids += fmt::format(R"({}{{"name": {}, "grid": {}, "material": {}, "ply_meshes": [{}]}})", fluids.empty() ? "" : ",\n  ",
                          str(name), str(name), material(rs.phaseMaterials[p], name), meshes);
  }
  std::string containers;  // the solids, then the render stage's props: meshes alike
  auto addMesh = [&](const SolidSpec& shape, const MaterialSpec& m) {
    containers += (containers.empty() ? "" : ",\n  ") + containerMesh(shape, m);
  };
  for (size_t j = 0; j < scene.solids.size(); ++j) addMesh(scene.solids[j], rs.solidMaterials[j]);
  for (const PropSpec& prop : rs.props) addMesh(prop.shape, prop.material);
  // A moving camera: its pose at every exported frame, keyed frame by frame in Blender.
  std::string cameraFrames;
  if (!rs.cameraKeys.empty())
    for (int f = first; f <= last; ++f) {
      const CameraKey c = render::cameraAt(rs.cameraKeys, f / scene.frameRate);
      cameraFrames += fmt::format("{}{{\"frame\": {}, \"position\": {}, \"look_at\": {}, \"fov_vertical_degrees\": {}}}",
                                  cameraFrames.empty() ? "" : ",\n  ", f, vec(c.position), vec(c.lookAt), num(c.fov));
    }
  // Everything in the scene's coordinates (y up, metres); the script turns them to Blender's z up.
  const std::string manifest = fmt::format(
      "{{\"format\": \"multifluid blender manifest 1\",\n"
      " \"scene\": {}, \"run_folder\": {}, \"up_axis\": \"Y\",\n"
      " \"fps\": {}, \"frame_start\": {}, \"frame_end\": {}, \"surface_first_file\": {}, \"voxel_size\": {},\n"
      " \"shutter\": {},\n"
      " \"camera\": {{\"position\": {}, \"look_at\": {}, \"fov_vertical_degrees\": {}, \"framing\": {}}},\n"
      " \"camera_frames\": [{}],\n"
      " \"image\": {{\"width\": {}, \"height\": {}, \"samples\": {}, \"max_depth\": {}}},\n"
      " \"light\": {{\"position\": {}, \"radius\": {}, \"emission\": {}}},\n"
      " \"sky\": {{\"zenith\": {}, \"horizon\": {}, \"ground\": {}}},\n"
      " \"floor\": {{\"enabled\": {}, \"height\": {}, \"checker_size\": {}}},\n"
      " \"meshes\": {},\n"
      " \"fluids\": [{}],\n"
      " \"containers\": [{}]}}\n",
      str(scene.name), str(dir.string()), num(scene.frameRate), first, last, str(surfaceFile(first).string()),
      num(stages.surfacing.voxelRatio * scene.solver.particleSpacing), num(rs.shutter), vec(rs.cameraPosition), vec(rs.lookAt), num(rs.fov),
      str(rs.cameraFraming), cameraFrames, rs.width, rs.height, rs.samples, rs.maxDepth,
      vec(rs.lightPosition), num(rs.lightRadius), vec(rs.lightEmission), vec(rs.skyZenith), vec(rs.skyHorizon), vec(rs.skyGround),
      rs.floor ? "true" : "false", num(rs.floorHeight), num(rs.checkerSize), str(opt.meshes), fluids, containers);
  const fs::path manifestFile = out.string() + ".json";
  writeFileAtomically(manifestFile.string(), manifest);

  // Blender writes a temporary of this process's own beside the output; only a clean exit with
  // the file there replaces the .blend (a failed export never leaves a partial one).
  const fs::path tmp = out.parent_path() / fmt::format("{}.tmp{}.blend", out.stem().string(), ::getpid());
  const fs::path log = out.string() + ".log", errLog = out.string() + ".err.log";
  const std::vector<std::string> argv = {"blender", "-b", "--factory-startup", "--python-exit-code", "1", "-P", script, "--",
                                         manifestFile.string(), tmp.string()};
  fmt::print(stderr, "export: frames {}-{} of {} ({} fluid(s), {} container(s)) -> {}\n", first, last, opt.runDir, rs.phases.size(),
             scene.solids.size(), out.string());
  SpawnOptions so;
  so.stdoutFile = log.string();
  so.stderrFile = errLog.string();
  so.timeoutSeconds = opt.timeoutSeconds;
  std::error_code ec;
  int status = -1;
  try {
    status = runProgram(argv, so);
  } catch (const std::exception& e) {
    fs::remove(tmp, ec);
    throw std::runtime_error(fmt::format("export: {}; Blender's log: {}", e.what(), log.string()));
  }
  if (status != 0 || !fs::is_regular_file(tmp, ec) || fs::file_size(tmp, ec) == 0) {
    fs::remove(tmp, ec);
    throw std::runtime_error(fmt::format("export: blender exited with status {} and {} ({}):\n{}{}", status,
                                         status == 0 ? "wrote no file" : "no file was kept", log.string(), tail(errLog, 3000),
                                         tail(log, 1500)));
  }
  fs::rename(tmp, out);
  fs::remove(errLog, ec);
  fmt::print(stderr, "export: wrote {} (manifest {}, Blender's log {})\n", out.string(), manifestFile.string(), log.string());
  return 0;
}

}  // namespace mf::pipeline
