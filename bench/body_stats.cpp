// body_stats: the bodies of fluid in a run's particle frames (sim/bodies.h), the measures issue 23
// states the paper's scenes in. A body is a connected set of particles of one fluid, linked within
// `link` spacings (1.5).
//
//   body_stats DIR [mid=Y] [link=1.5]
//
// Per frame and fluid: particles, bodies, the largest body, bodies of 8 or more particles, the
// share of the fluid in bodies under 10 particles ("spray"); "risen": bodies of 2-50 % of the fluid
// (blobs, not the pool, not spray) whose centroid is above y = mid (default: the middle of the
// containers, from the scene as run, DIR/scene.toml); "under": bodies of 8 or more whose top is
// below a denser fluid's particle within 2 spacings across (bubbles under a surface), and the
// particles that are; "round": the mean roundness
// of bodies of 20-200 particles (1 a ball). Then, over the run, per fluid:
//   - risen events: risen bodies that share no particle with a risen body of the frame before;
//   - returns: risen bodies of one frame whose particles are, in the next, mostly in the fluid's
//     largest body;
//   - bursts: bodies of 8 or more that were under a surface in one frame and whose particles are
//     all gone (removed) or no longer under one in the next;
//   - the most risen and under-surface bodies at once, the largest spray share, and what is under a
//     surface in the last frame.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "sim/bodies.h"
#include "sim/particle_io.h"
#include "sim/scene_file.h"
#include "bench_args.h"

namespace fs = std::filesystem;
using namespace mf;

namespace {

struct PhaseFrame {
  std::set<int64_t> risenIds;                 // particles of risen bodies
  std::vector<std::vector<int64_t>> risen;    // each risen body's ids
  std::vector<std::vector<int64_t>> under;    // each under-surface body (8+) 's ids
  std::set<int64_t> largestIds, underIds;
};

struct PhaseTotals {
  int risenEvents = 0, returns = 0, bursts = 0;
  size_t mostRisen = 0, mostUnder = 0, lastUnderParticles = 0, lastUnderBodies = 0;
  double worstSpray = 0, worstSprayTime = 0;
};

// The highest particle of each fluid per column of one spacing across (x, z): what "under a
// surface" is judged against.
struct Columns {
  Real cell = 1;
  std::map<std::pair<int64_t, int64_t>, std::map<int32_t, Real>> top;
  Columns(const ParticleFrame& fr, Real spacing) : cell(spacing) {
    for (size_t k = 0; k < fr.size(); ++k) {
      Real& t = top[key(fr.position[k])].try_emplace(fr.phase[k], -1e30).first->second;
      t = std::max(t, fr.position[k].y);
    }
  }
  std::pair<int64_t, int64_t> key(const Vec3& x) const {
    return {int64_t(std::floor(x.x / cell)), int64_t(std::floor(x.z / cell))};
  }
  /// Whether a denser fluid than `phase` has a particle above height y within 2 columns of x.
  bool under(const Vec3& x, Real y, int32_t phase, const std::vector<Real>& restDensity) const {
    const auto [cx, cz] = key(x);
    for (int64_t a = cx - 2; a <= cx + 2; ++a)
      for (int64_t b = cz - 2; b <= cz + 2; ++b) {
        const auto it = top.find({a, b});
        if (it == top.end()) continue;
        for (const auto& [p, t] : it->second)
          if (restDensity[size_t(p)] > restDensity[size_t(phase)] && t > y) return true;
      }
    return false;
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    fmt::print(stderr, "usage: body_stats DIR [mid=Y] [link=1.5]\n");
    return 2;
  }
  const fs::path dir = argv[1];
  double mid = std::nan(""), link = 1.5;
  for (int i = 2; i < argc; ++i) {
    if (std::strncmp(argv[i], "mid=", 4) == 0) mid = bench::number("mid", argv[i] + 4);
    else if (std::strncmp(argv[i], "link=", 5) == 0) link = bench::number("link", argv[i] + 5);
    else {
      fmt::print(stderr, "body_stats: unknown argument '{}' (mid=Y, link=SPACINGS)\n", argv[i]);
      return 2;
    }
  }
  std::map<int32_t, PhaseFrame> before;
  std::map<int32_t, PhaseTotals> totals;
  std::vector<std::string> names;
  int frames = 0;
  try {
    // The scene as run: the fluids' rest densities, and the containers' heights for `mid`.
    const Scene scene = loadScene((dir / "scene.toml").string());
    std::vector<Real> restDensity;
    for (const PhaseSpec& ph : scene.phases) restDensity.push_back(ph.restDensity);
    if (std::isnan(mid)) {
      Real lo = scene.domainMin.y, hi = scene.domainMax.y;
      if (!scene.solids.empty()) {
        lo = 1e30, hi = -1e30;
        for (const SolidSpec& so : scene.solids) {
          const bool box = so.shape == SolidSpec::Shape::Box;
          const Real top = box ? so.max.y : so.base.y + (so.profile.empty() ? so.height : so.profile.back().first);
          lo = std::min(lo, box ? so.min.y : so.base.y), hi = std::max(hi, top);
        }
      }
      mid = 0.5 * (lo + hi);
      fmt::print("mid = {:.4f} m (half way up the {}; set mid=Y)\n", mid, scene.solids.empty() ? "domain" : "containers");
    }
    for (int f = 0;; ++f) {
      const fs::path file = dir / "particles" / fmt::format("particles.{:04d}.vdb", f);
      if (!fs::exists(file)) {
        if (f == 0) throw std::runtime_error(file.string() + ": no such particle file (is DIR a run folder with a sim stage?)");
        break;
      }
      const ParticleFrame fr = readParticleFrame(file.string());
      names = fr.info.phaseNames;
      const Real s = Real(fr.info.particleSpacing);
      const Columns columns(fr, s);
      const FluidBodies fb = findBodies(fr.position.data(), fr.phase.data(), fr.size(), link * s);
      std::map<int32_t, size_t> count;
      for (int32_t p : fr.phase) ++count[p];
      // A fluid with no particle left has nothing under a surface (its last frame's figures are not kept).
      for (auto& [p, t] : totals)
        if (!count.count(p)) t.lastUnderParticles = t.lastUnderBodies = 0;
      std::map<int32_t, PhaseFrame> now;
      std::string line = fmt::format("frame {:4d} t {:7.3f}", f, fr.info.time);
      for (const auto& [p, n] : count) {
        PhaseFrame& pf = now[p];
        size_t bodies = 0, eight = 0, spray = 0, roundN = 0;
        double round = 0;
        const FluidBody* largest = nullptr;
        for (const FluidBody& b : fb.bodies) {
          if (b.phase != p) continue;
          if (!largest) largest = &b;
          ++bodies;
          eight += b.size() >= 8;
          if (b.size() < 10) spray += b.size();
          if (b.size() >= 20 && b.size() <= 200) round += b.roundness, ++roundN;
          std::vector<int64_t> ids;
          for (uint32_t i : b.members) ids.push_back(fr.id[i]);
          const double share = double(b.size()) / double(n);
          if (&b != largest && share >= 0.02 && share <= 0.5 && b.centroid.y > mid) {
            pf.risenIds.insert(ids.begin(), ids.end());
            pf.risen.push_back(ids);
          }
          if (b.size() >= 8 && columns.under(b.centroid, b.upper.y, p, restDensity)) {
            pf.underIds.insert(ids.begin(), ids.end());
            pf.under.push_back(ids);
          }
          if (&b == largest) pf.largestIds.insert(ids.begin(), ids.end());
        }
        size_t underParticles = 0;
        for (size_t k = 0; k < fr.size(); ++k) underParticles += fr.phase[k] == p && columns.under(fr.position[k], fr.position[k].y, p, restDensity);
        PhaseTotals& t = totals[p];
        t.lastUnderParticles = underParticles;
        const double sprayShare = double(spray) / double(n);
        if (sprayShare > t.worstSpray) t.worstSpray = sprayShare, t.worstSprayTime = fr.info.time;
        t.mostRisen = std::max(t.mostRisen, pf.risen.size());
        t.mostUnder = std::max(t.mostUnder, pf.under.size());
        t.lastUnderBodies = pf.under.size();
        auto prev = before.find(p);
        for (const auto& ids : pf.risen) {
          bool seen = false;
          if (prev != before.end())
            for (int64_t id : ids) seen |= prev->second.risenIds.count(id) > 0;
          t.risenEvents += !seen;
        }
        if (prev != before.end()) {
          for (const auto& ids : prev->second.risen) {
            size_t inPool = 0;
            for (int64_t id : ids) inPool += pf.largestIds.count(id);
            t.returns += 2 * inPool > ids.size();
          }
          for (const auto& ids : prev->second.under) {
            bool stillUnder = false;
            for (int64_t id : ids) stillUnder |= pf.underIds.count(id) > 0;
            t.bursts += !stillUnder;
          }
        }
        line += fmt::format(" | {} {} in {} bodies, largest {}, 8+ {}, spray {:.1f} %, risen {}, under {} ({} particles)", names.at(size_t(p)), n,
                            bodies, largest ? largest->size() : 0, eight, 100 * sprayShare, pf.risen.size(), pf.under.size(), underParticles);
        if (roundN) line += fmt::format(", round {:.3f} ({} bodies of 20-200)", round / double(roundN), roundN);
      }
      fmt::print("{}\n", line);
      before = std::move(now);
      ++frames;
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "body_stats: {}\n", e.what());
    return 1;
  }
  fmt::print("over {} frames (link {} spacings, mid {:.4f} m):\n", frames, link, mid);
  for (const auto& [p, t] : totals)
    fmt::print("  {}: risen events {}, returns {}, bursts {}, at once: risen {} under {}; spray at most {:.2f} % (t {:.2f} s); "
               "last frame under a surface: {} bodies of 8+, {} particles in all\n",
               names.at(size_t(p)), t.risenEvents, t.returns, t.bursts, t.mostRisen, t.mostUnder, 100 * t.worstSpray,
               t.worstSprayTime, t.lastUnderBodies, t.lastUnderParticles);
  return 0;
}
