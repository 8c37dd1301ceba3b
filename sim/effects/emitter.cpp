// Emitters and sinks: particles that enter and leave a scene (a tap pouring into a glass, a
// burner feeding flames, a drain).
//  - A nozzle ([[effects.emitter.disc]] or [[effects.emitter.box]]) emits layers of particles on
//    a square lattice of the particle spacing, in the plane through its centre perpendicular to
//    its velocity: a disc of the given radius, or the cross-section of a box. Layer k leaves at
//    t_k = start + k tau (tau = layer size / rate; rate 0 = s/|v|, consecutive layers one spacing
//    apart, the rest-density stream) while t_k <= end, and is placed where it would be at the
//    end of the step in which it is due, x = centre + offset + v (t - t_k), so the layers of a
//    stream are evenly spaced whatever the time step. New particles get the phase's material
//    values and mass (the seeding rule), the nozzle's velocity and temperature.
//  - A sink ([[effects.emitter.sink]]) removes every particle (of one phase, or of all) inside
//    its box at the end of each step.
// The layers emitted so far are the state that goes into checkpoints; ids come from the
// simulation's counter. A nozzle inside existing fluid compresses it: keep nozzles in the open.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "../simulation.h"
#include "builtin.h"

namespace mf::effects {

namespace {

struct Nozzle {
  uint16_t phase = 0;
  Vec3 centre, velocity;
  std::vector<Vec3> offsets;  // lattice points of one layer, relative to the centre
  Real start = 0, end = 0, interval = 0;
  Real temperature = 20;
};

struct Sink {
  Vec3 min, max;
  int phase = -1;  // -1: every phase
};

/// Square lattice of spacing s in the plane perpendicular to `axis`, centred on the origin,
/// keeping the points for which keep(p) is true.
template <class F>
std::vector<Vec3> planeLattice(const Vec3& axis, Real s, Real reach, F&& keep) {
  const Vec3 a = normalize(axis);
  // The world axis least aligned with a gives the first in-plane direction.
  Vec3 e(1, 0, 0);
  if (std::fabs(a.y) < std::fabs(a.x) && std::fabs(a.y) <= std::fabs(a.z)) e = {0, 1, 0};
  else if (std::fabs(a.z) < std::fabs(a.x) && std::fabs(a.z) < std::fabs(a.y)) e = {0, 0, 1};
  const Vec3 u = normalize(cross(a, e)), w = cross(a, u);
  const int n = int(std::ceil(reach / s)) + 1;
  std::vector<Vec3> out;
  for (int j = -n; j <= n; ++j)
    for (int i = -n; i <= n; ++i) {
      const Vec3 p = u * (i * s) + w * (j * s);
      if (keep(p)) out.push_back(p);
    }
  return out;
}

class Emitter final : public Effect {
 public:
  Emitter(const Scene& scene, std::vector<Nozzle> nozzles, std::vector<Sink> sinks)
      : phases_(scene.phases), masses_(phaseParticleMasses(scene)), nozzles_(std::move(nozzles)), sinks_(std::move(sinks)), emitted_(nozzles_.size(), 0),
        removed_(sinks_.size(), 0) {}
  const char* name() const override { return "emitter"; }
  AttributeMask requiredAttributes() const override { return 0; }
  void accumulateForces(const StepContext&, ParticleSet&) override {}
  bool editsParticles() const override { return true; }

  void editParticles(const StepContext& ctx, const ParticleSet& ps, ParticleEdits& edits) override {
    for (size_t s = 0; s < sinks_.size(); ++s) {
      const Sink& k = sinks_[s];
      for (size_t i = 0; i < ps.size(); ++i) {
        const Vec3& x = ps.position[i];
        if (edits.remove[i] || (k.phase >= 0 && ps.phase[i] != k.phase)) continue;
        if (x.x >= k.min.x && x.y >= k.min.y && x.z >= k.min.z && x.x <= k.max.x && x.y <= k.max.y && x.z <= k.max.z) {
          edits.remove[i] = 1;
          ++removed_[s];
        }
      }
    }
    const Real t = ctx.time;  // the end of the step just taken
    for (size_t k = 0; k < nozzles_.size(); ++k) {
      const Nozzle& nz = nozzles_[k];
      for (;;) {
        const Real tk = nz.start + Real(emitted_[k]) * nz.interval;
        if (tk > t || tk > nz.end) break;
        const Vec3 shift = nz.velocity * (t - tk);
        for (const Vec3& o : nz.offsets)
          edits.births.push_back(newParticleOfPhase(phases_[nz.phase], nz.phase, masses_[nz.phase], nz.centre + o + shift,
                                                    nz.velocity, nz.temperature));
        ++emitted_[k];
      }
    }
  }

  std::vector<uint8_t> saveState() const override {
    std::vector<uint8_t> b((emitted_.size() + removed_.size()) * sizeof(uint64_t));
    std::memcpy(b.data(), emitted_.data(), emitted_.size() * sizeof(uint64_t));
    std::memcpy(b.data() + emitted_.size() * sizeof(uint64_t), removed_.data(), removed_.size() * sizeof(uint64_t));
    return b;
  }
  void loadState(const std::vector<uint8_t>& b) override {
    if (b.size() != (emitted_.size() + removed_.size()) * sizeof(uint64_t))
      throw std::runtime_error("checkpoint: emitter state has the wrong size");
    std::memcpy(emitted_.data(), b.data(), emitted_.size() * sizeof(uint64_t));
    std::memcpy(removed_.data(), b.data() + emitted_.size() * sizeof(uint64_t), removed_.size() * sizeof(uint64_t));
  }

  std::vector<std::pair<std::string, double>> statistics() const override {
    std::vector<std::pair<std::string, double>> out;
    for (size_t k = 0; k < nozzles_.size(); ++k) {
      out.push_back({fmt::format("nozzle{}.emitted", k), double(emitted_[k] * nozzles_[k].offsets.size())});
      out.push_back({fmt::format("nozzle{}.per_layer", k), double(nozzles_[k].offsets.size())});
    }
    for (size_t s = 0; s < sinks_.size(); ++s) out.push_back({fmt::format("sink{}.removed", s), double(removed_[s])});
    return out;
  }

 private:
  std::vector<PhaseSpec> phases_;
  std::vector<Real> masses_;  // per phase
  std::vector<Nozzle> nozzles_;
  std::vector<Sink> sinks_;
  std::vector<uint64_t> emitted_;  // layers emitted per nozzle (checkpointed)
  std::vector<uint64_t> removed_;  // particles removed per sink (checkpointed, for reports)
};

std::vector<EffectParam> nozzleParams(bool disc) {
  std::vector<EffectParam> p = {
      {"phase", 1, 0, 0, {}, "", "the phase emitted", 1},
      {"velocity", 3, -1e3, 1e3, {}, "m/s", "velocity of the emitted particles (also the nozzle's axis); not zero"},
      {"rate", 1, 0, 1e9, {0.0}, "particles/s", "0: one layer per spacing travelled (a stream at rest density)"},
      {"start", 1, 0, 1e6, {0.0}, "s", "first layer"},
      {"end", 1, 0, 1e6, {1e6}, "s", "no layer after this time"},
      {"temperature", 1, -273.15, 1e4, {20.0}, "deg C", "temperature of the emitted particles (if the scene has temperature)"}};
  if (disc) {
    p.insert(p.begin() + 1, {"centre", 3, -1e6, 1e6, {}, "m", "centre of the disc"});
    p.insert(p.begin() + 2, {"radius", 1, 1e-6, 1e3, {}, "m", "radius of the disc (perpendicular to the velocity)"});
  } else {
    p.insert(p.begin() + 1, {"min", 3, -1e6, 1e6, {}, "m", "box corner"});
    p.insert(p.begin() + 2, {"max", 3, -1e6, 1e6, {}, "m", "box corner; layers are the box's cross-section through its centre"});
  }
  return p;
}

std::vector<std::pair<std::string, std::string>> checkNozzle(const ParamValues& v) {
  std::vector<std::pair<std::string, std::string>> problems;
  if (lengthSquared(v.vector("velocity")) == 0) problems.push_back({"velocity", "must not be zero (it is the nozzle's axis)"});
  if (v.number("end") < v.number("start")) problems.push_back({"end", "must not be before start"});
  if (v.params.count("min")) {
    const Vec3 lo = v.vector("min"), hi = v.vector("max");
    for (int a = 0; a < 3; ++a)
      if (!(lo[a] < hi[a])) {
        problems.push_back({"max", "must be greater than min in every component"});
        break;
      }
  }
  return problems;
}

}  // namespace

EffectInfo emitterInfo() {
  EffectInfo info{
      "emitter",
      "nozzles that emit particles (a disc or a box cross-section, at a rate and velocity, between start and end) and sinks that remove them",
      {},
      [](const EffectSpec& spec, const Scene& scene) {
        const Real s = scene.solver.particleSpacing;
        std::vector<Nozzle> nozzles;
        for (const char* kind : {"disc", "box"})
          for (const ParamValues& v : spec.list(kind)) {
            Nozzle nz;
            nz.phase = uint16_t(v.number("phase"));
            nz.velocity = v.vector("velocity");
            const bool disc = std::strcmp(kind, "disc") == 0;
            if (disc) {
              nz.centre = v.vector("centre");
              const Real R = v.number("radius");
              nz.offsets = planeLattice(nz.velocity, s, R, [&](const Vec3& p) { return lengthSquared(p) <= R * R * (1 + 1e-9); });
            } else {
              const Vec3 lo = v.vector("min"), hi = v.vector("max");
              nz.centre = (lo + hi) * 0.5;
              const Vec3 half = (hi - lo) * 0.5;
              nz.offsets = planeLattice(nz.velocity, s, length(half), [&](const Vec3& p) {
                return std::fabs(p.x) <= half.x * (1 + 1e-9) && std::fabs(p.y) <= half.y * (1 + 1e-9) &&
                       std::fabs(p.z) <= half.z * (1 + 1e-9);
              });
            }
            if (nz.offsets.empty()) nz.offsets.push_back({});  // a nozzle narrower than a spacing: one particle
            const Real rate = v.number("rate");
            nz.interval = rate > 0 ? Real(nz.offsets.size()) / rate : s / length(nz.velocity);
            nz.start = v.number("start");
            nz.end = v.number("end");
            nz.temperature = v.number("temperature");
            nozzles.push_back(nz);
          }
        std::vector<Sink> sinks;
        for (const ParamValues& v : spec.list("sink")) sinks.push_back({v.vector("min"), v.vector("max"), int(v.number("phase"))});
        return std::make_unique<Emitter>(scene, std::move(nozzles), std::move(sinks));
      }};
  info.lists = {{"disc", "a round nozzle", nozzleParams(true), checkNozzle},
                {"box", "a rectangular nozzle", nozzleParams(false), checkNozzle},
                {"sink",
                 "a box that removes the particles inside it",
                 {{"min", 3, -1e6, 1e6, {}, "m", "box corner"},
                  {"max", 3, -1e6, 1e6, {}, "m", "box corner"},
                  {"phase", 1, 0, 0, {-1.0}, "", "only this phase (default: every phase)", 1}},
                 [](const ParamValues& v) {
                   std::vector<std::pair<std::string, std::string>> problems;
                   const Vec3 lo = v.vector("min"), hi = v.vector("max");
                   for (int a = 0; a < 3; ++a)
                     if (!(lo[a] < hi[a])) {
                       problems.push_back({"max", "must be greater than min in every component"});
                       break;
                     }
                   return problems;
                 }}};
  info.check = [](const EffectSpec& spec, const Scene&) {
    std::vector<std::pair<std::string, std::string>> problems;
    if (spec.list("disc").empty() && spec.list("box").empty() && spec.list("sink").empty())
      problems.push_back({"disc", "no [[effects.emitter.disc]], [[effects.emitter.box]] or [[effects.emitter.sink]] entry"});
    return problems;
  };
  return info;
}

}  // namespace mf::effects
