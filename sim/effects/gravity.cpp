// Body force f = m g (Mueller et al. 2005, eq. 8 external force), optionally ramped in from zero
// over ramp_time with 0.5 (1 - cos(pi t / T)): a fluid seeded without its hydrostatic pressure
// then settles instead of being struck by full gravity at t = 0.
#include <tbb/parallel_for.h>

#include <cmath>

#include "builtin.h"

namespace mf::effects {

namespace {

class Gravity final : public Effect {
 public:
  Gravity(const Vec3& g, Real rampTime) : g_(g), rampTime_(rampTime) {}
  const char* name() const override { return "gravity"; }
  void accumulateForces(const StepContext& ctx, ParticleSet& ps) override {
    const Vec3 g = g_ * rampFactor(ctx.time);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 2048), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) ps.force[i] += g * ps.mass[i];
    });
  }

 private:
  Real rampFactor(Real t) const {
    if (rampTime_ <= 0 || t >= rampTime_) return 1;
    return 0.5 * (1 - std::cos(kPi * t / rampTime_));
  }
  Vec3 g_;
  Real rampTime_;
};

}  // namespace

EffectInfo gravityInfo() {
  return {"gravity",
          "uniform gravitational acceleration",
          {{"acceleration", 3, -1e4, 1e4, {0, -9.81, 0}, "m/s^2", "gravity vector"},
           {"ramp_time", 1, 0, 1e4, {0.0}, "s", "gravity rises smoothly from 0 to full over this time (0: full from the start)"}},
          [](const EffectSpec& spec, const Scene&) {
            return std::make_unique<Gravity>(spec.vector("acceleration"), spec.number("ramp_time"));
          }};
}

}  // namespace mf::effects
