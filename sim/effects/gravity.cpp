// Body force f = m g (Mueller et al. 2005, eq. 8 external force).
#include <tbb/parallel_for.h>

#include "builtin.h"

namespace mf::effects {

namespace {

class Gravity final : public Effect {
 public:
  explicit Gravity(const Vec3& g) : g_(g) {}
  const char* name() const override { return "gravity"; }
  void accumulateForces(const StepContext&, ParticleSet& ps) override {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 2048), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) ps.force[i] += g_ * ps.mass[i];
    });
  }

 private:
  Vec3 g_;
};

}  // namespace

EffectInfo gravityInfo() {
  return {"gravity",
          "uniform gravitational acceleration",
          {{"acceleration", 3, -1e4, 1e4, {0, -9.81, 0}, "m/s^2", "gravity vector"}},
          [](const EffectSpec& spec, const Scene&) {
            return std::make_unique<Gravity>(spec.vector("acceleration"));
          }};
}

}  // namespace mf::effects
