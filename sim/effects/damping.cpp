// Velocity damping F = -beta m v, optionally only until a given time. Used to relax an initial
// state to rest (a column dropped onto its own weight rings in its acoustic mode for seconds
// otherwise); it does not move the equilibrium, only the way there.
#include <tbb/parallel_for.h>

#include "builtin.h"

namespace mf::effects {

namespace {

class Damping final : public Effect {
 public:
  Damping(Real rate, Real until) : rate_(rate), until_(until) {}
  const char* name() const override { return "damping"; }
  void accumulateForces(const StepContext& ctx, ParticleSet& ps) override {
    if (ctx.time >= until_) return;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 2048), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) ps.force[i] -= ps.velocity[i] * (rate_ * ps.mass[i]);
    });
  }
  Real maxTimeStep(const StepContext&, const ParticleSet&) const override {
    return 0.5 / rate_;  // explicit decay stays monotone for rate dt <= 1/2
  }

 private:
  Real rate_, until_;
};

}  // namespace

EffectInfo dampingInfo() {
  return {"damping",
          "velocity damping -beta m v for relaxing a start state (until a given time)",
          {{"rate", 1, 1e-6, 1e6, {10.0}, "1/s", "beta"},
           {"until", 1, 0, 1e9, {1e9}, "s", "damping stops at this time"}},
          [](const EffectSpec& spec, const Scene&) {
            return std::make_unique<Damping>(spec.number("rate"), spec.number("until"));
          }};
}

}  // namespace mf::effects
