// Diffusion of a particle attribute, dA/dt = alpha lap A (Mueller et al. 2005, section 4.2),
// with the paper's symmetric SPH form
//   dA_i/dt = sum_j V_j alpha_ij (A_j - A_i) lap W_visc(r_ij)
// where alpha_ij is the harmonic mean of the two fluids' diffusivities (flux continuity across
// an interface between different materials; 0 if either is an insulator). The kernel is the
// viscosity kernel, whose Laplacian is positive everywhere, so heat only flows downhill. Its
// lattice moment is normalised once (sum_j V (x_j)^2 lap W = 2, as for the exact Laplacian of x^2),
// the way the pressure gradient is. Free surfaces and walls are insulating.
// Sources: boxes that exchange with a held value at a rate (Newton's law), dA/dt += r (A_s - A).
// Explicit Euler inside the stability limit dt <= factor / max_i(sum_j V_j alpha_ij lap W_ij + r):
// with factor <= 1 every new value is a convex mix of old ones (no over- or undershoot).
// Two instances: heat_diffusion (temperature) and dye_diffusion (a passive dye).
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>

#include "../simulation.h"
#include "builtin.h"

namespace mf::effects {

namespace {

struct Source {
  Vec3 min, max;
  Real value = 0, rate = 0;
};

class Diffusion final : public Effect {
 public:
  Diffusion(const char* name, Attribute attribute, std::vector<Real> ParticleSet::*field, std::vector<Real> diffusivity,
            std::vector<Source> sources, Real stabilityFactor, Real spacing)
      : name_(name),
        attribute_(attribute),
        field_(field),
        diffusivity_(std::move(diffusivity)),
        sources_(std::move(sources)),
        stabilityFactor_(stabilityFactor),
        spacing_(spacing) {}
  const char* name() const override { return name_; }
  AttributeMask requiredAttributes() const override { return bit(attribute_); }

  void accumulateForces(const StepContext& ctx, ParticleSet& ps) override {
    const SphKernels& K = ctx.kernels;
    if (normH_ != K.h) {
      const Real s = spacing_, V = 1.0 / latticeKernelSum(K, s);
      const Real moment = sumOverRestLattice(K, s, [&](int a, int b, int c) {
        const Real r = s * std::sqrt(Real(a * a + b * b + c * c));
        return V * (a * s) * (a * s) * K.viscosityLaplacian(r);
      });
      norm_ = 2.0 / moment;
      normH_ = K.h;
    }
    const std::vector<Real>& A = ps.*field_;
    const size_t n = ps.size();
    rate_.resize(n);
    const NeighborLists& nf = ctx.fluidNeighbors;
    maxRowSum_ = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, n, 512), Real(0),
        [&](const tbb::blocked_range<size_t>& range, Real rowMax) {
          for (size_t i = range.begin(); i != range.end(); ++i) {
            const Vec3 xi = ps.position[i];
            const Real ai = diffusivity_[ps.phase[i]], Ai = A[i];
            Real sum = 0, row = 0;
            for (uint64_t k = nf.begin(i), e = nf.end(i); k < e; ++k) {
              const uint32_t j = nf.indices[k];
              const Real aj = diffusivity_[ps.phase[j]];
              const Real aij = ai == aj ? ai : (ai + aj > 0 ? 2 * ai * aj / (ai + aj) : 0);
              if (aij == 0) continue;
              const Real c = ps.volume[j] * aij * norm_ * K.viscosityLaplacian(length(ctx.periodic.separation(xi, ps.position[j])));
              sum += c * (A[j] - Ai);
              row += c;
            }
            for (const Source& s : sources_)
              if (xi.x >= s.min.x && xi.y >= s.min.y && xi.z >= s.min.z && xi.x <= s.max.x && xi.y <= s.max.y &&
                  xi.z <= s.max.z) {
                sum += s.rate * (s.value - Ai);
                row += s.rate;
              }
            rate_[i] = sum;
            rowMax = std::max(rowMax, row);
          }
          return rowMax;
        },
        [](Real a, Real b) { return std::max(a, b); });
  }

  Real maxTimeStep(const StepContext&, const ParticleSet&) const override {
    return maxRowSum_ > 0 ? stabilityFactor_ / maxRowSum_ : std::numeric_limits<Real>::infinity();
  }

  void advance(const StepContext&, ParticleSet& ps, Real dt) override {
    std::vector<Real>& A = ps.*field_;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 4096), [&](const auto& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) A[i] += dt * rate_[i];
    });
  }

 private:
  const char* name_;
  Attribute attribute_;
  std::vector<Real> ParticleSet::*field_;
  std::vector<Real> diffusivity_;  // per phase, m^2/s
  std::vector<Source> sources_;
  Real stabilityFactor_, spacing_;
  Real norm_ = 1, normH_ = 0, maxRowSum_ = 0;
  std::vector<Real> rate_;  // dA/dt at the step's start
};

EffectInfo diffusionInfo(const char* name, const char* doc, Attribute attribute, std::vector<Real> ParticleSet::*field,
                         Real PhaseSpec::*diffusivity, const char* phaseKey, const char* valueKey,
                         const char* valueUnit) {
  EffectInfo info{
      name,
      doc,
      {{"stability_factor", 1, 1e-3, 1, {0.5}, "", "dt <= factor / max_i (sum_j V_j alpha_ij lap W_ij + source rates)"}},
      [=](const EffectSpec& spec, const Scene& scene) {
        std::vector<Real> alpha;
        for (const PhaseSpec& p : scene.phases) alpha.push_back(p.*diffusivity);
        std::vector<Source> sources;
        for (const ParamValues& v : spec.list("source"))
          sources.push_back({v.vector("min"), v.vector("max"), v.number(valueKey), v.number("rate")});
        return std::make_unique<Diffusion>(name, attribute, field, alpha, sources, spec.number("stability_factor"),
                                           scene.solver.particleSpacing);
      }};
  info.lists = {{"source",
                 "a box whose particles exchange with a held value (a heater, a cooler)",
                 {{"min", 3, -1e6, 1e6, {}, "m", "box corner"},
                  {"max", 3, -1e6, 1e6, {}, "m", "box corner"},
                  {valueKey, 1, -1e6, 1e6, {}, valueUnit, "the value held"},
                  {"rate", 1, 0, 1e6, {}, "1/s", "exchange rate r in dA/dt = r (A_s - A)"}}}};
  info.phaseKeys = {phaseKey};
  return info;
}

}  // namespace

EffectInfo heatDiffusionInfo() {
  return diffusionInfo("heat_diffusion", "heat conduction dT/dt = alpha lap T, alpha per phase (thermal_diffusivity), heat sources",
                       Attribute::Temperature, &ParticleSet::temperature, &PhaseSpec::thermalDiffusivity,
                       "thermal_diffusivity", "temperature", "deg C");
}

EffectInfo dyeDiffusionInfo() {
  return diffusionInfo("dye_diffusion", "diffusion of a passive dye, alpha per phase (dye_diffusivity), dye sources",
                       Attribute::Dye, &ParticleSet::dye, &PhaseSpec::dyeDiffusivity, "dye_diffusivity",
                       "concentration", "");
}

}  // namespace mf::effects
