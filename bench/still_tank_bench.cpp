// still_tank_bench: water 10 cm deep at rest in a closed 20 x 30 x 20 cm box at 1 cm spacing
// (4 000 particles), the still tank of issue 21 ("max speed <= 1e-3 m/s after 2 s"). For each of
// our pressure solvers it prints, at the times asked for, the largest and the median speed, the
// count faster than 5 cm/s, the mean density error and the highest particle; then the peer
// (SPlisHSPlasH, ../shared/peer) on the same tank in the same run, read from its VTK output.
//
//   still_tank_bench [--end 2] [--solvers dfsph,wcsph] [--peer DIR|none] [--peer-limit 300] [--set key=value]...
//
// The peer's tank is its UnitBox scaled to 20 x 30 x 20 cm with Akinci boundary particles and,
// on a second run, volume maps; its fluid block is 20 x 10 x 20 particles at radius 5 mm, as ours.
#include <fmt/format.h>
#include <signal.h>
#include <sys/wait.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "bench_args.h"

namespace {

namespace fs = std::filesystem;

const char* kStillTank = R"([scene]
name = "still_tank"
end_time = 2.0
frame_rate = 10
domain_min = [-0.05, -0.05, -0.05]
domain_max = [0.25, 0.35, 0.25]
[solver]
particle_spacing = 0.01
max_dt = 0.005
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 1000.0
viscosity = 0.01
[[solid]]
name = "tank"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.2, 0.3, 0.2]
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.2, 0.1, 0.2]
[effects.gravity]
acceleration = [0.0, -9.81, 0.0]
[effects.pressure]
[effects.viscosity]
)";

struct Snapshot {
  double time = 0, vmax = 0, vmedian = 0, meanError = 0, top = 0;
  size_t fast = 0, n = 0;
};

Snapshot measure(double t, const std::vector<float>& xyz, const std::vector<float>& vel, const std::vector<double>& theta) {
  Snapshot s;
  s.time = t;
  s.n = xyz.size() / 3;
  std::vector<double> speed(s.n);
  for (size_t i = 0; i < s.n; ++i) {
    speed[i] = std::sqrt(double(vel[3 * i]) * vel[3 * i] + double(vel[3 * i + 1]) * vel[3 * i + 1] + double(vel[3 * i + 2]) * vel[3 * i + 2]);
    s.top = std::max(s.top, double(xyz[3 * i + 1]));
    if (speed[i] > 0.05) ++s.fast;
  }
  for (double th : theta) s.meanError += th - 1;
  s.meanError = theta.empty() ? std::nan("") : s.meanError / double(theta.size());  // the peer's VTK has no density
  if (s.n == 0) return s;
  std::sort(speed.begin(), speed.end());
  s.vmax = speed.back();
  s.vmedian = speed[s.n / 2];
  return s;
}

void print(const std::string& who, const Snapshot& s, const std::string& extra) {
  const std::string error = std::isnan(s.meanError) ? "  n/a  " : fmt::format("{:+.4f}", s.meanError);
  fmt::print("{:<22} t={:4.2f} s  vmax={:8.4f} m/s  median={:8.5f} m/s  >5cm/s={:5}/{}  mean(rho/rho0-1)={}  top={:.4f} m  {}\n",
             who, s.time, s.vmax, s.vmedian, s.fast, s.n, error, s.top, extra);
  std::fflush(stdout);
}

void runOurs(const std::string& solver, double end, const std::vector<std::string>& sets) {
  std::vector<std::string> overrides = {"solver.pressure=" + solver, fmt::format("scene.end_time={}", end)};
  overrides.insert(overrides.end(), sets.begin(), sets.end());
  mf::Simulation sim(mf::parseScene(kStillTank, "still_tank.toml", overrides));
  for (double t : {0.5, 1.0, 1.5, 2.0, 3.0, 4.0}) {
    if (t > end + 1e-9) break;
    sim.advanceTo(t);
    const auto& ps = sim.particles();
    std::vector<float> x, v;
    std::vector<double> theta;
    for (size_t i = 0; i < ps.size(); ++i) {
      for (int a = 0; a < 3; ++a) x.push_back(float(ps.position[i][a])), v.push_back(float(ps.velocity[i][a]));
      theta.push_back(ps.density[i] / ps.restDensity[i]);
    }
    const auto& c = sim.counters();
    print("ours " + solver, measure(t, x, v, theta), fmt::format("steps={} clamps={} retries={}", c.steps, c.wallClamps, c.retries));
  }
}

// Big-endian float arrays after the "POINTS" and "velocity" headers of SPlisHSPlasH's legacy VTK.
bool readVtk(const fs::path& path, std::vector<float>& xyz, std::vector<float>& vel) {
  std::ifstream in(path, std::ios::binary);
  const std::string d((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto array = [&](const std::string& tag, std::vector<float>& out) {
    const size_t at = d.find(tag);
    if (at == std::string::npos) return false;
    const size_t eol = d.find('\n', at);
    std::istringstream header(d.substr(at, eol - at));
    std::string word;
    size_t n = 0;
    header >> word;
    if (tag == "POINTS ") header >> n;
    else header >> word >> n;  // "velocity 3 N float"
    if (eol == std::string::npos || eol + 1 + 12 * n > d.size()) return false;
    out.resize(3 * n);
    for (size_t k = 0; k < 3 * n; ++k) {
      uint32_t u;
      std::memcpy(&u, d.data() + eol + 1 + 4 * k, 4);
      u = __builtin_bswap32(u);
      std::memcpy(&out[k], &u, 4);
    }
    return true;
  };
  return array("POINTS ", xyz) && array("velocity ", vel);
}

void runPeer(const fs::path& peer, bool volumeMaps, double end, int limit) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("still_tank_peer_{}_{}", ::getpid(), volumeMaps ? "vmap" : "akinci");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "scene.json") << fmt::format(
      R"({{"Configuration": {{"particleRadius": 0.005, "numberOfStepsPerRenderUpdate": 1, "simulationMethod": 4,
 "gravitation": [0,-9.81,0], "boundaryHandlingMethod": {}, "stopAt": {}, "enableVTKExport": true,
 "enablePartioExport": false, "dataExportFPS": 2, "particleAttributes": "velocity", "enableZSort": true,
 "timeStepSize": 0.001, "cflMethod": 1, "cflFactor": 1, "cflMaxTimeStepSize": 0.005,
 "DFSPH": {{"minIterations": 2, "maxIterations": 100, "maxError": 0.05, "maxIterationsV": 100, "maxErrorV": 0.1, "enableDivergenceSolver": true}}}},
 "Materials": [{{"id": "Fluid", "density0": 1000, "viscosityMethod": 1, "Standard viscosity": {{"viscosity": 0.01}}}}],
 "RigidBodies": [{{"geometryFile": "{}", "translation": [0.1,0.15,0.1], "rotationAxis": [1,0,0], "rotationAngle": 0,
   "scale": [0.2,0.3,0.2], "isDynamic": false, "isWall": true, "mapInvert": true, "mapThickness": 0.0, "mapResolution": [20,30,20]}}],
 "FluidBlocks": [{{"denseMode": 0, "start": [-0.0025,-0.0025,-0.0025], "end": [0.2025,0.1025,0.2025], "translation": [0,0,0], "scale": [1,1,1]}}]}})",
      volumeMaps ? 2 : 0, end, (peer / "data" / "UnitBox.obj").string());
  std::fflush(stdout);
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (::chdir((peer / "bin").c_str()) != 0) _exit(127);
    const std::string log = (dir / "log.txt").string(), out = (dir / "run").string(), scene = (dir / "scene.json").string();
    if (!std::freopen(log.c_str(), "w", stdout) || !std::freopen(log.c_str(), "a", stderr)) _exit(127);
    ::setenv("OMP_NUM_THREADS", "1", 1);
    ::execl("./SPHSimulator", "SPHSimulator", "--no-gui", "--no-initial-pause", "--output-dir", out.c_str(), scene.c_str(), nullptr);
    _exit(127);
  }
  // A peer run whose particles leak out of the tank slows to a crawl (its CFL step follows
  // them): it is stopped after `limit` seconds and judged on the frames it wrote.
  int status = 0;
  bool stopped = false;
  for (int waited = 0; ::waitpid(pid, &status, WNOHANG) == 0; ++waited) {
    if (waited >= 10 * limit) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      stopped = true;
      break;
    }
    ::usleep(100000);
  }
  const std::string who = volumeMaps ? "peer dfsph volume map" : "peer dfsph akinci";
  if (stopped) fmt::print("{:<22} stopped after {} s (its frames so far follow)\n", who, limit);
  else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    fmt::print("{:<22} failed (see {})\n", who, (dir / "log.txt").string());
    return;
  }
  // Frame k of the export is at t = (k - 1) / 2 s.
  for (int k = 2;; ++k) {
    std::vector<float> x, v;
    if (!readVtk(dir / "run" / "vtk" / fmt::format("ParticleData_Fluid_{}.vtk", k), x, v)) break;
    print(who, measure(0.5 * (k - 1), x, v, {}), "");
  }
  fs::remove_all(dir);
}

}  // namespace

int main(int argc, char** argv) {
  double end = 2;
  int peerLimit = 300;
  std::vector<std::string> solvers = {"dfsph", "wcsph"}, sets;
  fs::path peer = "../shared/peer";  // from the project root, as pressure_bench
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool more = i + 1 < argc;
    if (a == "--end" && more) end = mf::bench::number(a, argv[++i]);
    else if (a == "--solvers" && more) {
      solvers.clear();
      std::stringstream ss(argv[++i]);
      for (std::string s; std::getline(ss, s, ',');) solvers.push_back(s);
    } else if (a == "--peer" && more) peer = argv[++i];
    else if (a == "--set" && more) sets.push_back(argv[++i]);
    else if (a == "--peer-limit" && more) peerLimit = int(mf::bench::whole(a, argv[++i]));
    else {
      fmt::print(stderr, "usage: still_tank_bench [--end 2] [--solvers dfsph,wcsph] [--peer DIR|none] [--peer-limit S] [--set key=value]...\n");
      return 2;
    }
  }
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
  for (const std::string& s : solvers) runOurs(s, end, sets);
  if (peer != "none") {
    if (!fs::exists(peer / "bin" / "SPHSimulator")) fmt::print("peer: no {} (pass --peer DIR or none)\n", (peer / "bin" / "SPHSimulator").string());
    else
      for (bool vmap : {false, true}) runPeer(fs::absolute(peer), vmap, end, peerLimit);
  }
  return 0;
}
