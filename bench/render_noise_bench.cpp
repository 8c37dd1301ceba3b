// Noise of the path tracer against a high-spp reference, on two small canned scenes of the
// golden tests: the ball of water in a glass (dielectrics, the table, sphere light and sky) and
// a wax blob in the lava lamp (a dense scattering medium lit from below).
//   ./build/bench/render_noise_bench [--ref-spp N] [--ref-dir DIR] [--spp a,b,...] [--set render.KEY=VALUE]...
//                                    [--denoise iterations|sigma_luminance|normal_power|sigma_depth|sigma_albedo=V]...
//                                    [--scenes glass,lamp] [--equal-time false] [--compare-spp N]
// The reference is rendered once with indirect_clamp = 0 (no bias from the clamp) and kept in
// DIR (default /tmp/mf_noise_ref) as raw floats, so that later renderers are measured against
// the same image; delete it to render it again. For every spp it prints
//   rel RMSE  sqrt(mean over pixels and channels of (x - r)^2 / (r^2 + 0.01))
//   black     the fraction of pixels with luminance < 5 % of the reference's (of the pixels
//             whose reference luminance is above 0.02)
//   time      wall seconds of one image (the best of the renders)
//   rel MAE   mean |x - r| / (r + 0.1): less moved by rare fireflies than the RMSE
// as the mean over 512 / spp renders with independent seeds (at most 64; one render's RMSE moves
// by a factor 4 with its fireflies).
// then the rel RMSE of the mean of those renders (an unbiased renderer's matches that of one
// render with all their samples), and, at the first spp, the frame-to-frame change on the static glass scene: the % of pixels
// that differ by more than 0.016 (idiff, as displayed) between frames 0 and 1.
// Denoised (render/denoise.h): for every spp the same renders denoised, their rel RMSE and MAE,
// the render's and the denoiser's wall time; then at equal time, the raw renderer at the spp
// whose render costs what the render plus the denoiser cost at this spp (the spp scaled by the
// ratio of the times, rounded), and the ratio of its rel RMSE to the denoised one's.
// Figures are in docs/rendering.md, with the renderer they belong to.
#include <fmt/format.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <tbb/info.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "bench/rel_rmse.h"
#include "render/denoise.h"
#include "render/path_tracer.h"
#include "pipeline/scene_stages.h"
#include "bench_args.h"

using namespace mf;

namespace {

const char* kGlass = R"(
[scene]
name = "glass"
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
width = 160
height = 90
camera_position = [0.0, 0.12, 0.45]
look_at = [0.0, 0.06, 0.0]
fov = 35
light_position = [0.3, 0.6, 0.4]
light_radius = 0.08
checker_size = 0.03
)";

// The lava_lamp scene's lamp, wax and light (configs/lava_lamp.toml) with one blob of wax above
// the bulb in place of the simulated wax.
const char* kLamp = R"(
[scene]
name = "lamp"
end_time = 1
frame_rate = 1
domain_min = [-0.2, -0.1, -0.2]
domain_max = [0.2, 1.3, 0.2]
[solver]
particle_spacing = 0.02
[[phase]]
name = "fluid"
rest_density = 500.0
[[phase]]
name = "wax"
rest_density = 1000.0
[[solid]]
name = "vessel"
shape = "revolution"
base = [0.0, 0.0, 0.0]
profile = [[0.0, 0.13], [0.35, 0.17], [0.8, 0.15], [1.15, 0.10]]
[[fluid]]
phase = "fluid"
min = [-0.1, 0.0, -0.1]
max = [0.1, 0.9, 0.1]
[effects.gravity]
[render]
width = 90
height = 160
camera_position = [0.0, 0.6, 2.6]
look_at = [0.0, 0.56, 0.0]
fov = 30
sky_zenith = [0.07, 0.07, 0.09]
sky_horizon = [0.07, 0.07, 0.09]
sky_ground = [0.07, 0.07, 0.09]
light_position = [0.0, -0.07, 0.0]
light_radius = 0.05
light_emission = [80.0, 60.0, 30.0]
floor = false
[render.material.fluid]
ior = 1.34
absorption = [3.0, 1.5, 0.3]
[render.material.wax]
kind = "medium"
ior = 1.44
absorption = [1.0, 12.0, 20.0]
scattering = 60.0
priority = 15
[render.material.vessel]
thickness = 0.006
)";

std::vector<std::string> extraKeys;  // --set KEY=VALUE, for the renders measured (not the reference)
render::DenoiseSettings denoiseSettings;  // --denoise KEY=VALUE (iterations, sigma_luminance, ...)

void setDenoise(const std::string& kv) {
  const size_t eq = kv.find('=');
  const std::string key = kv.substr(0, eq);
  const float v = eq == std::string::npos ? 0.0f : std::stof(kv.substr(eq + 1));
  if (key == "iterations") denoiseSettings.iterations = int(v);
  else if (key == "sigma_luminance") denoiseSettings.sigmaLuminance = v;
  else if (key == "normal_power") denoiseSettings.normalPower = v;
  else if (key == "sigma_depth") denoiseSettings.sigmaDepth = v;
  else if (key == "sigma_albedo") denoiseSettings.sigmaAlbedo = v;
  else throw std::runtime_error("--denoise: unknown key " + key + " (iterations, sigma_luminance, normal_power, sigma_depth, sigma_albedo)");
}

/// `animated`: the frame in the sampler's seed, so that frames are independent renders (a
/// renderer without the animated_seed key keys by frame always).
std::unique_ptr<render::PathTracer> makeScene(const std::string& name, int spp, bool reference, bool animated = false) {
  std::vector<std::string> overrides = {fmt::format("render.samples={}", spp)};
  if (reference) overrides.push_back("render.indirect_clamp=0");
  else overrides.insert(overrides.end(), extraKeys.begin(), extraKeys.end());
  const char* text = name == "glass" ? kGlass : kLamp;
  SceneStages sc;
  try {
    auto withSeed = overrides;
    if (animated) withSeed.push_back("render.animated_seed=true");
    sc = parseSceneStages(text, name, withSeed);
  } catch (const std::exception&) {
    sc = parseSceneStages(text, name, overrides);
  }
  std::vector<render::Surface> surfaces;
  if (name == "glass") {
    auto ball = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(0.045f, openvdb::Vec3f(0, 0.05f, 0), 0.002f, 3.0f);
    surfaces.push_back({"water", render::levelSetMesh(*ball), sc.render.phaseMaterials[0]});
  } else {
    auto blob = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(0.09f, openvdb::Vec3f(0.02f, 0.15f, 0), 0.004f, 3.0f);
    surfaces.push_back({"wax", render::levelSetMesh(*blob), sc.render.phaseMaterials[1]});
  }
  for (auto& s : render::solidSurfaces(sc.scene, sc.render)) surfaces.push_back(std::move(s));
  return std::make_unique<render::PathTracer>(std::move(surfaces), sc.render);
}

double luminance(const render::Image& im, size_t p) {
  return 0.2126 * im.rgb[3 * p] + 0.7152 * im.rgb[3 * p + 1] + 0.0722 * im.rgb[3 * p + 2];
}

struct Error {
  double relRmse = 0, black = 0, relMae = 0;
};

Error measure(const render::Image& x, const render::Image& r) {
  Error e;
  size_t lit = 0, black = 0;
  for (size_t i = 0; i < r.rgb.size(); ++i) e.relMae += std::abs(double(x.rgb[i]) - r.rgb[i]) / (std::abs(double(r.rgb[i])) + 0.1);
  e.relMae /= r.rgb.size();
  e.relRmse = bench::relRmse(x, r);
  for (size_t p = 0; p < r.rgb.size() / 3; ++p) {
    const double lr = luminance(r, p);
    if (lr <= 0.02) continue;
    ++lit;
    if (luminance(x, p) < 0.05 * lr) ++black;
  }
  e.black = lit ? double(black) / lit : 0;
  return e;
}

constexpr int kZoom = 4;  // the canned frames are small: images written for looking at are 4x

/// `im` with each pixel a kZoom x kZoom block.
render::Image zoomed(const render::Image& im) {
  render::Image out(im.width * kZoom, im.height * kZoom);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) out.set(x, y, im.at(x / kZoom, y / kZoom));
  return out;
}

/// A grey map of a per-pixel error, white at its largest (square root: the error's scale), zoomed.
void writeErrorMap(const std::string& path, const std::vector<double>& perPixel, int width, int height) {
  const double worst = perPixel.empty() ? 0 : *std::max_element(perPixel.begin(), perPixel.end());
  render::Image map(width, height);
  for (size_t p = 0; p < perPixel.size(); ++p) {
    const float v = worst > 0 ? float(std::sqrt(perPixel[p] / worst)) : 0.f;
    map.rgb[3 * p] = map.rgb[3 * p + 1] = map.rgb[3 * p + 2] = v;
  }
  render::writeImage(path, zoomed(map));
}

render::Image reference(const std::string& name, int spp, const std::string& dir) {
  const std::string path = fmt::format("{}/{}_{}spp.f32", dir, name, spp);
  render::Image im;
  if (std::ifstream in{path, std::ios::binary}) {
    in.read(reinterpret_cast<char*>(&im.width), sizeof(int));
    in.read(reinterpret_cast<char*>(&im.height), sizeof(int));
    im.rgb.resize(size_t(im.width) * im.height * 3);
    in.read(reinterpret_cast<char*>(im.rgb.data()), im.rgb.size() * sizeof(float));
    render::writeImage(fmt::format("{}/{}_{}spp.png", dir, name, spp), zoomed(im));
    fmt::print("  reference {} (read)\n", path);
    return im;
  }
  render::RenderStats st;
  im = makeScene(name, spp, true)->render(0, &st);
  std::filesystem::create_directories(dir);
  std::ofstream out{path, std::ios::binary};
  out.write(reinterpret_cast<const char*>(&im.width), sizeof(int));
  out.write(reinterpret_cast<const char*>(&im.height), sizeof(int));
  out.write(reinterpret_cast<const char*>(im.rgb.data()), im.rgb.size() * sizeof(float));
  render::writeImage(fmt::format("{}/{}_{}spp.exr", dir, name, spp), im);
  render::writeImage(fmt::format("{}/{}_{}spp.png", dir, name, spp), zoomed(im));
  fmt::print("  reference {} rendered in {:.1f} s\n", path, st.seconds);
  return im;
}

/// `reps` renders of frames 1..reps (animated seeds), raw and (with `denoised`) denoised.
struct Runs {
  Error raw, denoised;
  double renderSeconds = 1e30, denoiseSeconds = 1e30;  // the best of the renders
  render::Image mean, last, lastDenoised;
  render::Image denoisedMean;        // the denoiser's bias, with the noise of all the renders' samples
  std::vector<double> denoisedError;  // per pixel, the denoised renders' summed (x - r)^2 / (r^2 + 0.01)
};

Runs runs(const render::PathTracer& tracer, const render::Image& ref, int reps, bool denoised) {
  Runs r;
  r.mean = render::Image(ref.width, ref.height);
  r.denoisedMean = render::Image(ref.width, ref.height);
  r.denoisedError.assign(ref.rgb.size() / 3, 0.0);
  double mse = 0, dmse = 0;
  for (int rep = 0; rep < reps; ++rep) {
    render::RenderStats st;
    render::Aovs aovs;
    r.last = tracer.render(rep + 1, &st, {}, nullptr, denoised ? &aovs : nullptr);
    for (size_t i = 0; i < r.last.rgb.size(); ++i) r.mean.rgb[i] += r.last.rgb[i] / reps;
    r.renderSeconds = std::min(r.renderSeconds, st.seconds);
    const Error one = measure(r.last, ref);
    mse += one.relRmse * one.relRmse / reps, r.raw.black += one.black / reps, r.raw.relMae += one.relMae / reps;
    if (!denoised) continue;
    const auto t0 = std::chrono::steady_clock::now();
    r.lastDenoised = render::denoise(r.last, aovs, denoiseSettings);
    r.denoiseSeconds = std::min(r.denoiseSeconds, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    for (size_t i = 0; i < ref.rgb.size(); ++i) r.denoisedMean.rgb[i] += r.lastDenoised.rgb[i] / reps;
    const std::vector<double> e = bench::relSquaredErrorPerPixel(r.lastDenoised, ref);
    for (size_t p = 0; p < e.size(); ++p) r.denoisedError[p] += e[p];
    const Error d = measure(r.lastDenoised, ref);
    dmse += d.relRmse * d.relRmse / reps, r.denoised.black += d.black / reps, r.denoised.relMae += d.relMae / reps;
  }
  r.raw.relRmse = std::sqrt(mse), r.denoised.relRmse = std::sqrt(dmse);
  return r;
}

int repsFor(int spp) { return std::max(1, std::min(64, 512 / spp)); }

}  // namespace

int main(int argc, char** argv) {
  openvdb::initialize();
  int refSpp = 4096;
  int compareSpp = 0;  // --compare-spp N: print the N-spp reference's error against the reference
  std::string dir = "/tmp/mf_noise_ref", sppList = "8", sceneList = "glass,lamp";
  bool equalTime = true;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--ref-spp") refSpp = int(bench::whole(a, argv[i + 1]));
    else if (a == "--ref-dir") dir = argv[i + 1];
    else if (a == "--spp") sppList = argv[i + 1];
    else if (a == "--scenes") sceneList = argv[i + 1];
    else if (a == "--equal-time") equalTime = std::string(argv[i + 1]) != "false";
    else if (a == "--set") extraKeys.push_back(argv[i + 1]);
    else if (a == "--denoise") setDenoise(argv[i + 1]);
    else if (a == "--compare-spp") compareSpp = int(bench::whole(a, argv[i + 1]));
  }
  std::vector<int> spps;
  for (long n : bench::wholeList("--spp", sppList)) spps.push_back(int(n));
  fmt::print("render_noise_bench: reference {} spp, {} threads\n", refSpp, tbb::info::default_concurrency());
  std::vector<std::string> names;
  std::stringstream sl(sceneList);
  for (std::string t; std::getline(sl, t, ',');) names.push_back(t);
  for (const std::string& name : names) {
    const render::Image ref = reference(name, refSpp, dir);
    if (compareSpp > 0) {
      // The reference's own noise: a lower-spp reference of the same seed against this one (its
      // first samples are the same, so the figure is sqrt(1 - compare/ref) of its noise).
      const render::Image other = reference(name, compareSpp, dir);
      fmt::print("  {:<5} the {}-spp reference against the {}-spp one: rel RMSE {:.4f}\n", name, compareSpp, refSpp,
                 measure(other, ref).relRmse);
    }
    for (int spp : spps) {
      // Rel RMSE and black: over `reps` independent renders (frames 1..reps with animated
      // seeds), as one pixel's firefly moves the figure of a single render by a lot.
      const int reps = repsFor(spp);
      auto tracer = makeScene(name, spp, false, true);
      const Runs r = runs(*tracer, ref, reps, true);
      const Error& e = r.raw;
      fmt::print("  {:<5} {:>5} spp: rel RMSE {:.4f}  rel MAE {:.4f}  black {:.2f} %  time {:.3f} s  ({} renders)\n", name, spp,
                 e.relRmse, e.relMae, 100 * e.black, r.renderSeconds, reps);
      if (reps > 1)  // unbiased: the mean of the renders has the error of reps * spp samples
        fmt::print("        mean of the {} renders ({} spp): rel RMSE {:.4f}\n", reps, reps * spp, measure(r.mean, ref).relRmse);
      const Error& d = r.denoised;
      fmt::print("        denoised: rel RMSE {:.4f}  rel MAE {:.4f}  black {:.2f} %  time {:.3f} s + denoiser {:.3f} s\n", d.relRmse,
                 d.relMae, 100 * d.black, r.renderSeconds, r.denoiseSeconds);
      if (reps > 1) {
        // Where the denoised error is: its share in the worst pixels, and a map (white: the worst).
        std::vector<double> sorted = r.denoisedError;
        std::sort(sorted.begin(), sorted.end(), std::greater<>());
        double total = 0, top1 = 0, top10 = 0;
        for (size_t k = 0; k < sorted.size(); ++k) {
          total += sorted[k];
          if (k < sorted.size() / 100) top1 += sorted[k];
          if (k < sorted.size() / 10) top10 += sorted[k];
        }
        fmt::print("        mean of the {} denoised renders: rel RMSE {:.4f}; the worst 1 % / 10 % of pixels hold {:.0f} % / {:.0f} % "
                   "of the denoised squared error (map: {}_{}spp_error.png)\n",
                   reps, measure(r.denoisedMean, ref).relRmse, total > 0 ? 100 * top1 / total : 0.0,
                   total > 0 ? 100 * top10 / total : 0.0, name, spp);
        writeErrorMap(fmt::format("{}/{}_{}spp_error.png", dir, name, spp), r.denoisedError, ref.width, ref.height);
        // The same for the mean of the denoised renders: the denoiser's bias.
        writeErrorMap(fmt::format("{}/{}_{}spp_bias.png", dir, name, spp), bench::relSquaredErrorPerPixel(r.denoisedMean, ref),
                      ref.width, ref.height);
      }
      render::writeImage(fmt::format("{}/{}_{}spp_now.png", dir, name, spp), zoomed(r.last));
      render::writeImage(fmt::format("{}/{}_{}spp_denoised.png", dir, name, spp), zoomed(r.lastDenoised));
      render::writeImage(fmt::format("{}/{}_{}spp_denoised_mean.png", dir, name, spp), zoomed(r.denoisedMean));
      // Equal time: raw samples for the render's and the denoiser's time together.
      if (!equalTime) continue;
      const int eqSpp = std::max(spp, int(std::lround(spp * (r.renderSeconds + r.denoiseSeconds) / r.renderSeconds)));
      auto eqTracer = makeScene(name, eqSpp, false, true);
      const Runs eq = runs(*eqTracer, ref, repsFor(eqSpp), false);
      fmt::print("        equal time: raw {} spp rel RMSE {:.4f} (time {:.3f} s, {} renders); raw / denoised rel RMSE {:.2f}x"
                 " (the issue's target: 4x)\n",
                 eqSpp, eq.raw.relRmse, eq.renderSeconds, repsFor(eqSpp), eq.raw.relRmse / d.relRmse);
    }
  }
  auto glass = makeScene("glass", spps.front(), false);
  const auto d = render::compareImages(glass->render(0), glass->render(1), 0.016);
  fmt::print("  glass frame 0 -> 1 at {} spp: {:.1f} % of pixels differ by more than 0.016\n", spps.front(), d.failedPercent());
  auto animated = makeScene("glass", spps.front(), false, true);
  const auto da = render::compareImages(animated->render(0), animated->render(1), 0.016);
  fmt::print("  (with animated_seed: {:.1f} %)\n", da.failedPercent());
  return 0;
}
