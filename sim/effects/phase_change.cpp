// Phase transition (Mueller et al. 2005, section 5.2: boiling water) and the heat that drives it.
//
// phase_change, after every accepted step:
//  - Evaporation. A liquid particle hotter than the boiling temperature becomes vapour where
//    vapour can nucleate: within site_radius of one of the N cavitation sites (points drawn at
//    random, seeded, in a box on the heated bottom; the paper: 5), or next to vapour that has
//    finished expanding (a bubble grows by evaporating the hot water at its wall, a shell at a
//    time). With latent_heat = L / c_p > 0 it first stores its superheat, held at the boiling
//    temperature, and evaporates once the store holds L / c_p: the boil-off is then the heat
//    delivered over L, whatever the steps (without it, boiling's 6 s boiled off 85-369 water
//    particles as only the steps changed; 54-70 at 60 K). Condensing gives L / c_p back. Its phase, viscosity,
//    stiffness and colours become the vapour's; its mass is kept.
//  - Expansion. The new vapour particle starts at the liquid's rest density, which then falls
//    towards the vapour's at expansion_rate, rho0 <- max(rho0_v, rho0 exp(-r dt)), but never so
//    fast that the particle's compression rho/rho0 - 1 exceeds 25 % (half the watchdog's default
//    limit): the vapour pushes the water aside (the bubble grows) at the pace the pressure can
//    move it. Jumping straight to the vapour's rest density would make the particle 10x
//    compressed, which the watchdog rightly refuses. With mass kept a particle's density never
//    falls below its own kernel weight and the wall's share (0.385 rho0_w at h = 2 spacings), so
//    the expansion also stops where the neighbours still give a fifth of the density
//    (reachable()): a rest density below that is an error no pressure can remove. A bubble's
//    vapour thus ends at max(rho0_v, about 480 kg/m^3 at h = 2 spacings), and "finished
//    expanding" means within 5 % of that.
//  - Condensation. Vapour colder than boiling_temperature - condensation_margin becomes liquid
//    again: phase, rest density, viscosity, stiffness and colours of the liquid (at once: an
//    under-dense particle has zero pressure, nothing to refuse).
//    With wall_distance > 0, liquid that close to a container evaporates only at the sites
//    (nucleate boiling; measured without it: a vapour film of 420 particles along the glass
//    lifted all the water 3.6 cm in 0.5 s).
//  - Saturation (saturated = 1). Vapour, and liquid off the glass, are held at the boiling
//    temperature: heat beyond it is latent heat. Without it, growth into water that diffusion had
//    pushed past boiling made vapour at no energy cost (measured: 737 vapour particles threw 167
//    water particles out of the domain at 4.25 s).
//  - Leaving. Vapour at the top of the particle set (OpenSurfaceRule of colour_fields.h, the
//    rule trapped air uses) is removed: the bubble has burst. With leave_without_liquid = 1,
//    vapour with no liquid within h has left too (a gas layer above the water, which the
//    surface rule missed: 1 372 particles gathered there by 6.75 s).
// Decisions are made per particle from the state before any change, then applied; removals in
// index order: the same result on any number of threads.
//
// flame_heating: the flame particles heat the glass, the glass heats the water. The wall samples
// carry no temperature, so the glass's heated bottom is one heat exchanger with one temperature
// T_g (checkpointed): it follows the mean temperature of the flame particles in a box under the
// glass, dT_g/dt = r_f (T_flames - T_g) (unchanged while no flame is there), and liquid particles
// in a box just inside the bottom follow it, dT_i/dt = r_l (min(T_g, T_max) - T_i). Both are
// integrated exactly over the step (exponential decay), so no time-step limit. T_max stands for
// what the simplification leaves out: water boiling on the glass keeps it a little above 100 deg C
// however hot the flame, and the glass itself does not lose heat.
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "../simulation.h"
#include "builtin.h"
#include "../solids.h"
#include "colour_fields.h"

namespace mf::effects {

namespace {

uint64_t splitmix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
Real uniform01(uint64_t x) { return Real(splitmix(x) >> 11) * (1.0 / 9007199254740992.0); }

bool inBox(const Vec3& x, const Vec3& lo, const Vec3& hi) {
  return x.x >= lo.x && x.y >= lo.y && x.z >= lo.z && x.x <= hi.x && x.y <= hi.y && x.z <= hi.z;
}

struct PhaseChangeParams {
  uint16_t liquid = 0, vapour = 1;
  Real boiling = 100, margin = 2;
  int sites = 5;
  Vec3 siteMin, siteMax;
  uint64_t seed = 1;
  Real siteRadius = 1.5;  // spacings
  Real expansionRate = 20;
  Real wallDistance = 0;       // spacings; 0: no wall rule
  bool saturated = false;
  bool leaveWithoutLiquid = false;
  Real latent = 0;  // K: L / c_p
  OpenSurfaceRule open;
};

class PhaseChange final : public Effect {
 public:
  PhaseChange(const Scene& scene, PhaseChangeParams p) : p_(std::move(p)), liquid_(scene.phases.at(p_.liquid)), vapour_(scene.phases.at(p_.vapour)) {
    for (int k = 0; k < p_.sites; ++k) {
      const uint64_t base = splitmix(p_.seed * 0x100000001b3ULL + uint64_t(k));
      const Vec3 u(uniform01(base + 1), uniform01(base + 2), uniform01(base + 3));
      sites_.push_back({p_.siteMin.x + u.x * (p_.siteMax.x - p_.siteMin.x), p_.siteMin.y + u.y * (p_.siteMax.y - p_.siteMin.y),
                        p_.siteMin.z + u.z * (p_.siteMax.z - p_.siteMin.z)});
    }
    isLiquid_.assign(scene.phases.size(), 0);
    isLiquid_[p_.liquid] = 1;
    want_.assign(scene.phases.size(), 0);
    want_[p_.vapour] = 1;
    p_.open.up = normalize(p_.open.up);
    solids_ = scene.solids;
  }
  const char* name() const override { return "phase_change"; }
  AttributeMask requiredAttributes() const override {
    return bit(Attribute::Temperature) | (p_.latent > 0 ? bit(Attribute::Latent) : 0);
  }
  void accumulateForces(const StepContext&, ParticleSet&) override {}

  void advance(const StepContext& ctx, ParticleSet& ps, Real dt) override {
    const size_t n = ps.size();
    const NeighborLists& nf = ctx.fluidNeighbors;
    const Real r2site = (p_.siteRadius * ctx.particleSpacing) * (p_.siteRadius * ctx.particleSpacing);
    const Real wall = p_.wallDistance * ctx.particleSpacing;
    change_.assign(n, 0);
    // Where each vapour particle's expansion ends: the vapour's rest density, or the least it
    // can reach (reachable()), whichever is higher.
    expanded_.assign(n, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i)
        if (ps.phase[i] == p_.vapour) expanded_[i] = std::max(vapour_.restDensity, reachable(ctx, ps, i));
    });
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const Real T = ps.temperature[i];
        if (ps.phase[i] == p_.liquid && T > p_.boiling) {
          bool atSite = false;
          for (const Vec3& s : sites_) atSite |= lengthSquared(ps.position[i] - s) <= r2site;
          if (atSite) {
            change_[i] = 3;
            continue;
          }
          // On the glass (within wall_distance of a container's surface) only at the sites: with
          // the glass at most ~20 K above boiling, water boils nucleately, in bubbles from the
          // cavities; a bubble spreading along the glass as a vapour film is film boiling, which
          // needs a glass ~100 K hotter (Leidenfrost). Measured without this rule (boiling at
          // 5 mm, water started at 90 deg C): the vapour front ran along the whole heated bottom
          // and 420 vapour particles lifted all of the water 3.6 cm within 0.5 s.
          bool onGlass = false;
          if (wall > 0)
            for (const SolidSpec& so : solids_)
              onGlass |= insideFluidRegion(so, ps.position[i]) && !insideFluidRegion(so, ps.position[i], -wall);
          if (onGlass) continue;
          // Saturated (below): the superheat a growing bubble would take is latent heat that
          // has already gone, so bubbles grow only at their site and by expanding. Measured with
          // growth (5 mm, from 0 deg C): 1 394 of 2 385 evaporations by 4.5 s were growth into
          // water a step's diffusion had pushed past 100 deg C; the vapour piled up under the
          // water (287 particles at 4 s, 821 at 4.5 s) and threw 150 particles out of the domain.
          if (p_.saturated) continue;
          // Growth from vapour that has finished expanding (rest density within 5 % of where
          // its expansion ends): a bubble takes in the hot water at its wall one shell at a
          // time, at the pace of the expansion. Measured without that condition: in a pool at
          // 105 deg C the vapour front crossed a neighbourhood every step (200 m/s) and 1 088
          // of 1 152 particles flashed to vapour and left within 0.1 s.
          bool grows = false;
          for (uint64_t k = nf.begin(i), e = nf.end(i); k < e && !grows; ++k) {
            const uint32_t j = nf.indices[k];
            grows = ps.phase[j] == p_.vapour && ps.restDensity[j] <= 1.05 * expanded_[j];
          }
          change_[i] = grows ? 1 : 0;
        } else if (ps.phase[i] == p_.vapour && T < p_.boiling - p_.margin) {
          change_[i] = 2;
        }
      }
    });
    const Real decay = std::exp(-p_.expansionRate * dt);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        if ((change_[i] == 1 || change_[i] == 3) && p_.latent > 0) {
          // Latent heat: the superheat goes into the particle's store, and it evaporates once the
          // store holds L / c_p; what is beyond stays as the vapour's heat. So the boil-off is
          // the heat delivered over L, whatever the steps.
          ps.latent[i] += ps.temperature[i] - p_.boiling;
          ps.temperature[i] = p_.boiling;
          if (ps.latent[i] >= p_.latent) {
            ps.temperature[i] += ps.latent[i] - p_.latent;
            ps.latent[i] = 0;
          } else {
            change_[i] = 0;
          }
        }
        if (change_[i] == 1 || change_[i] == 3) becomes(ps, i, p_.vapour, vapour_, ps.restDensity[i]);
        else if (change_[i] == 2) {
          becomes(ps, i, p_.liquid, liquid_, liquid_.restDensity);
          ps.temperature[i] += p_.latent;  // condensing gives the latent heat back
        }
        else if (ps.phase[i] == p_.vapour) {
          // Expansion towards the vapour's rest density, at most 25 % compression at a time, and
          // no lower than the particle can reach (reachable(), eq. 3's own term).
          const Real target = std::max({ps.restDensity[i] * decay, ps.density[i] / 1.25, expanded_[i]});
          ps.restDensity[i] = std::min(ps.restDensity[i], target);
        }
        // Saturated: heat that takes vapour, or liquid off the glass, beyond the boiling
        // temperature is latent heat (it evaporates water, which leaves as vapour at the
        // surface and in the bubbles), not superheat. Only the heated layer on the glass
        // (wall_distance) may be hotter; that is where the sites make the bubbles. Measured
        // without the cap on the liquid (5 mm, from 0 deg C): the bulk superheated, bubbles grew
        // into it without paying any latent heat, and at 4.25 s 737 vapour particles threw 167
        // water particles out of the domain.
        if (p_.saturated) {
          bool capped = ps.phase[i] == p_.vapour;
          if (!capped && ps.phase[i] == p_.liquid && ps.temperature[i] > p_.boiling) {
            capped = true;
            for (const SolidSpec& so : solids_)
              capped &= !(insideFluidRegion(so, ps.position[i]) && !insideFluidRegion(so, ps.position[i], -wall));
          }
          if (capped) ps.temperature[i] = std::min(ps.temperature[i], p_.boiling);
        }
      }
    });
    for (size_t i = 0; i < n; ++i) {
      evaporated_ += change_[i] == 1 || change_[i] == 3;
      atSites_ += change_[i] == 3;
      condensed_ += change_[i] == 2;
    }
  }

  bool editsParticles() const override { return true; }
  void editParticles(const StepContext& ctx, const ParticleSet& ps, ParticleEdits& edits) override {
    computeColourGradients(ctx, ps, isLiquid_, want_, grad_);
    const size_t n = ps.size();
    leave_.assign(n, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i)
        if (ps.phase[i] == p_.vapour && p_.open.gradientSaysOpen(grad_.all[i], ctx.kernels.h)) leave_[i] = 1;
    });
    p_.open.confirmWithProbe(ctx, ps, leave_, 1);
    // Vapour out of the water: no liquid within h. The surface rule above needs a dense top
    // with nothing above it; vapour that has risen out of the water gathers as a layer of gas
    // (300 kg/m^3, at its rest density) on it and has neither. Measured without this (5 mm, from
    // 0 deg C, saturated): 1 372 vapour particles gathered above the water by 6.75 s, 1 left at
    // the surface, 31 out of the domain; a density threshold (below 0.5 rho0) changed nothing,
    // the layer is not thin. The cost: the core of a bubble wider than 2 h under water would go
    // too (with growth only at the sites, bubbles are a few particles).
    if (p_.leaveWithoutLiquid) {
      const NeighborLists& nf = ctx.fluidNeighbors;
      tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          if (ps.phase[i] != p_.vapour || leave_[i]) continue;
          bool liquid = false;
          for (uint64_t k = nf.begin(i), e = nf.end(i); k < e && !liquid; ++k) liquid = ps.phase[nf.indices[k]] == p_.liquid;
          if (!liquid) leave_[i] = 1;
        }
      });
    }
    for (size_t i = 0; i < n; ++i)
      if (leave_[i] && !edits.remove[i]) {
        edits.remove[i] = 1;
        ++left_;
      }
  }

  std::vector<uint8_t> saveState() const override {
    const uint64_t v[4] = {evaporated_, condensed_, left_, atSites_};
    return std::vector<uint8_t>(reinterpret_cast<const uint8_t*>(v), reinterpret_cast<const uint8_t*>(v) + sizeof v);
  }
  void loadState(const std::vector<uint8_t>& b) override {
    uint64_t v[4];
    if (b.size() != sizeof v) throw std::runtime_error("checkpoint: phase_change state has the wrong size");
    std::memcpy(v, b.data(), sizeof v);
    evaporated_ = v[0];
    condensed_ = v[1];
    left_ = v[2];
    atSites_ = v[3];
  }
  std::vector<std::pair<std::string, double>> statistics() const override {
    return {{"evaporated", double(evaporated_)}, {"condensed", double(condensed_)}, {"left_at_surface", double(left_)},
            {"evaporated_at_sites", double(atSites_)}};
  }
  const std::vector<Vec3>& sites() const { return sites_; }

 private:
  // The lowest rest density particle i can be held at. Its density never falls below its own
  // kernel weight and the wall's share, m_i W(0) + rho0_i sum_b V_b W_ib (simulation.cpp), even
  // with every fluid neighbour pushed out of h: with the water's mass that is 0.385 rho0_w at
  // h = 2 spacings. A rest density below it is an error no pressure can remove; DFSPH then
  // raises the pressure on the last neighbours at the kernel's edge without bound (measured at
  // 1 cm: rho0 = 362 under a floor of 382, 1.7 MPa, 1 291 m/s the next step). The expansion
  // stops where the neighbours still give a fifth of the density (kReach), as much as the
  // per-step cap lets one step compress.
  static Real reachable(const StepContext& ctx, const ParticleSet& ps, size_t i) {
    constexpr Real kReach = 1.25;
    Real wall = 0;
    for (uint64_t k = ctx.boundaryNeighbors.begin(i), e = ctx.boundaryNeighbors.end(i); k < e; ++k) {
      const uint32_t b = ctx.boundaryNeighbors.indices[k];
      wall += ctx.boundary.volume[b] * ctx.kernels.densityChecked(lengthSquared(ctx.periodic.separation(ctx.boundary.position[b], ps.position[i])));
    }
    // rho0 >= kReach (m W(0) + rho0 wall)
    const Real free = 1 - kReach * wall;
    return free > 0 ? kReach * ps.mass[i] * ctx.kernels.selfWeight / free : ps.restDensity[i];
  }

  static void becomes(ParticleSet& ps, size_t i, uint16_t phase, const PhaseSpec& ph, Real restDensity) {
    ps.phase[i] = phase;
    ps.restDensity[i] = restDensity;
    ps.viscosity[i] = ph.viscosity;
    ps.stiffness[i] = ph.stiffness;
    if (ps.has(Attribute::InterfaceColour)) ps.interfaceColour[i] = ph.interfaceColour;
    if (ps.has(Attribute::SurfaceColour)) ps.surfaceColour[i] = ph.surfaceColour;
  }

  PhaseChangeParams p_;
  PhaseSpec liquid_, vapour_;
  std::vector<Vec3> sites_;
  std::vector<SolidSpec> solids_;
  std::vector<uint8_t> isLiquid_, want_, change_, leave_;
  std::vector<Real> expanded_;
  ColourGradients grad_;
  uint64_t evaporated_ = 0, condensed_ = 0, left_ = 0, atSites_ = 0;
};

struct FlameHeatingParams {
  uint16_t flame = 0, liquid = 0;
  Vec3 flameMin, flameMax, wallMin, wallMax;
  Real flameRate = 1, liquidRate = 5, wallTemperature = 20, maxWallTemperature = 1e4;
};

class FlameHeating final : public Effect {
 public:
  explicit FlameHeating(FlameHeatingParams p) : p_(p), wallT_(p.wallTemperature) {}
  const char* name() const override { return "flame_heating"; }
  AttributeMask requiredAttributes() const override { return bit(Attribute::Temperature); }
  void accumulateForces(const StepContext&, ParticleSet&) override {}

  void advance(const StepContext&, ParticleSet& ps, Real dt) override {
    // Mean flame temperature in the box, summed in index order (the same bits on any thread count).
    Real sum = 0;
    size_t count = 0;
    for (size_t i = 0; i < ps.size(); ++i)
      if (ps.phase[i] == p_.flame && inBox(ps.position[i], p_.flameMin, p_.flameMax)) {
        sum += ps.temperature[i];
        ++count;
      }
    const Real seen = std::min(wallT_, p_.maxWallTemperature);
    const Real toLiquid = 1 - std::exp(-p_.liquidRate * dt);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 2048), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i)
        if (ps.phase[i] == p_.liquid && inBox(ps.position[i], p_.wallMin, p_.wallMax))
          ps.temperature[i] += (seen - ps.temperature[i]) * toLiquid;
    });
    if (count > 0) wallT_ += (sum / Real(count) - wallT_) * (1 - std::exp(-p_.flameRate * dt));
    flamesSeen_ = count;
  }

  std::vector<uint8_t> saveState() const override {
    std::vector<uint8_t> b(sizeof(Real) + sizeof(uint64_t));
    std::memcpy(b.data(), &wallT_, sizeof(Real));
    std::memcpy(b.data() + sizeof(Real), &flamesSeen_, sizeof(uint64_t));
    return b;
  }
  void loadState(const std::vector<uint8_t>& b) override {
    if (b.size() != sizeof(Real) + sizeof(uint64_t)) throw std::runtime_error("checkpoint: flame_heating state has the wrong size");
    std::memcpy(&wallT_, b.data(), sizeof(Real));
    std::memcpy(&flamesSeen_, b.data() + sizeof(Real), sizeof(uint64_t));
  }
  std::vector<std::pair<std::string, double>> statistics() const override {
    return {{"wall_temperature", wallT_}, {"flames_under_glass", double(flamesSeen_)}};
  }

 private:
  FlameHeatingParams p_;
  Real wallT_;
  uint64_t flamesSeen_ = 0;
};

std::vector<std::pair<std::string, std::string>> checkBox(const ParamValues& v, const char* lo, const char* hi,
                                                           bool pointAllowed = false) {
  const Vec3 a = v.vector(lo), b = v.vector(hi);
  for (int k = 0; k < 3; ++k)
    if (pointAllowed ? !(a[k] <= b[k]) : !(a[k] < b[k]))
      return {{hi, std::string(pointAllowed ? "must not be below " : "must be greater than ") + lo + " in any component"}};
  return {};
}

}  // namespace

EffectInfo phaseChangeInfo() {
  EffectInfo info{
      "phase_change",
      "boiling: liquid above the boiling temperature at a cavitation site (or next to vapour) becomes vapour, vapour that "
      "cools condenses, vapour at the surface leaves (section 5.2)",
      {{"liquid", 1, 0, 0, {}, "", "the liquid phase", 1},
       {"vapour", 1, 0, 0, {}, "", "its vapour phase", 1},
       {"boiling_temperature", 1, -273.15, 1e4, {100.0}, "deg C", "liquid hotter than this can evaporate"},
       {"condensation_margin", 1, 0, 1e3, {2.0}, "K", "vapour colder than boiling_temperature - margin condenses"},
       {"sites", 1, 0, 1e4, {5.0}, "", "number of cavitation sites (the paper: 5)", 0, true},
       {"site_min", 3, -1e6, 1e6, {}, "m", "box the sites are drawn in (the heated bottom)"},
       {"site_max", 3, -1e6, 1e6, {}, "m", "box corner"},
       {"seed", 1, 0, 9e15, {1.0}, "", "random seed of the sites"},
       {"site_radius", 1, 0, 10, {1.5}, "spacings", "liquid within this distance of a site can nucleate"},
       {"expansion_rate", 1, 0, 1e4, {20.0}, "1/s", "new vapour's rest density falls towards the vapour's at this rate"},
       {"wall_distance", 1, 0, 10, {0.0}, "spacings", "liquid this close to a container's surface evaporates only at the sites (nucleate boiling: no vapour film along the glass); 0: anywhere next to vapour"},
       {"saturated", 1, 0, 1, {0.0}, "", "1: vapour, and liquid off the glass (beyond wall_distance), never hotter than boiling_temperature: heat beyond it is latent heat that leaves with the vapour"},
       {"leave_without_liquid", 1, 0, 1, {0.0}, "", "1: vapour with no liquid within h (out of the water) leaves too"},
       {"latent_heat", 1, 0, 1e4, {0.0}, "K", "L / c_p: liquid evaporates once it has taken this much heat beyond boiling_temperature, and condensing gives it back (water: 540); 0: at once"},
       {"surface_threshold", 1, 0.01, 10, {0.6}, "1/h", "vapour with |grad c_a| above this at the top of the particles leaves"},
       {"surface_cosine", 1, -1, 1, {0.5}, "", "... with the normal pointing down: n . up < -surface_cosine"},
       {"probe", 1, 0, 3, {1.0}, "h", "... and no particles this far above it (0: no probe)"},
       {"up", 3, -1e3, 1e3, {0.0, 1.0, 0.0}, "", "the up direction"}},
      [](const EffectSpec& spec, const Scene& scene) {
        PhaseChangeParams p;
        p.liquid = uint16_t(spec.number("liquid"));
        p.vapour = uint16_t(spec.number("vapour"));
        p.boiling = spec.number("boiling_temperature");
        p.margin = spec.number("condensation_margin");
        p.sites = int(spec.number("sites"));
        p.siteMin = spec.vector("site_min");
        p.siteMax = spec.vector("site_max");
        p.seed = uint64_t(spec.number("seed"));
        p.siteRadius = spec.number("site_radius");
        p.expansionRate = spec.number("expansion_rate");
        p.wallDistance = spec.number("wall_distance");
        p.saturated = spec.number("saturated") != 0;
        p.leaveWithoutLiquid = spec.number("leave_without_liquid") != 0;
        p.latent = spec.number("latent_heat");
        p.open = {spec.number("surface_threshold"), spec.number("surface_cosine"), spec.number("probe"), spec.vector("up")};
        return std::make_unique<PhaseChange>(scene, p);
      }};
  info.check = [](const EffectSpec& spec, const Scene&) {
    std::vector<std::pair<std::string, std::string>> problems;
    if (spec.number("liquid") == spec.number("vapour")) problems.push_back({"vapour", "must differ from liquid"});
    if (lengthSquared(spec.vector("up")) == 0) problems.push_back({"up", "must not be zero"});
    for (const auto& pr : checkBox(spec, "site_min", "site_max", true)) problems.push_back(pr);
    return problems;
  };
  return info;
}

EffectInfo flameHeatingInfo() {
  EffectInfo info{
      "flame_heating",
      "flame particles under a glass heat its bottom (one exchanger temperature), which heats the liquid on it",
      {{"flame", 1, 0, 0, {}, "", "the flame phase", 1},
       {"liquid", 1, 0, 0, {}, "", "the liquid heated", 1},
       {"flame_min", 3, -1e6, 1e6, {}, "m", "box under the glass whose flame particles heat it"},
       {"flame_max", 3, -1e6, 1e6, {}, "m", "box corner"},
       {"wall_min", 3, -1e6, 1e6, {}, "m", "box just inside the glass bottom whose liquid it heats"},
       {"wall_max", 3, -1e6, 1e6, {}, "m", "box corner"},
       {"flame_rate", 1, 0, 1e4, {1.0}, "1/s", "r_f: dT_g/dt = r_f (mean flame temperature - T_g)"},
       {"liquid_rate", 1, 0, 1e4, {5.0}, "1/s", "r_l: dT/dt = r_l (min(T_g, max_wall_temperature) - T) for liquid in the wall box"},
       {"wall_temperature", 1, -273.15, 1e4, {20.0}, "deg C", "T_g at the start"},
       {"max_wall_temperature", 1, -273.15, 1e4, {1e4}, "deg C", "the liquid never sees the glass hotter than this"}},
      [](const EffectSpec& spec, const Scene&) {
        FlameHeatingParams p;
        p.flame = uint16_t(spec.number("flame"));
        p.liquid = uint16_t(spec.number("liquid"));
        p.flameMin = spec.vector("flame_min");
        p.flameMax = spec.vector("flame_max");
        p.wallMin = spec.vector("wall_min");
        p.wallMax = spec.vector("wall_max");
        p.flameRate = spec.number("flame_rate");
        p.liquidRate = spec.number("liquid_rate");
        p.wallTemperature = spec.number("wall_temperature");
        p.maxWallTemperature = spec.number("max_wall_temperature");
        return std::make_unique<FlameHeating>(p);
      }};
  info.check = [](const EffectSpec& spec, const Scene&) {
    std::vector<std::pair<std::string, std::string>> problems;
    if (spec.number("liquid") == spec.number("flame")) problems.push_back({"liquid", "must differ from flame"});
    for (const auto& pr : checkBox(spec, "flame_min", "flame_max")) problems.push_back(pr);
    for (const auto& pr : checkBox(spec, "wall_min", "wall_max")) problems.push_back(pr);
    return problems;
  };
  return info;
}

}  // namespace mf::effects
