#include "particles.h"

#include "parallel_util.h"

#include <utility>

namespace mf {

void ParticleSet::enable(AttributeMask mask) {
  attributes |= mask;
  const size_t n = size();
  if (has(Attribute::InterfaceColour)) interfaceColour.resize(n, 0);
  if (has(Attribute::SurfaceColour)) surfaceColour.resize(n, 1);
  if (has(Attribute::Temperature)) temperature.resize(n, 0);
  if (has(Attribute::Dye)) dye.resize(n, 0);
  if (has(Attribute::DivergencePressure)) divergencePressure.resize(n, 0);
  if (has(Attribute::Latent)) latent.resize(n, 0);
}

void ParticleSet::reserve(size_t n) {
  forEachArray([n](const char*, auto& v) { v.reserve(n); });
}

void ParticleSet::append(uint64_t newId, const ParticleInit& p) {
  id.push_back(newId);
  phase.push_back(p.phase);
  position.push_back(p.position);
  velocity.push_back(p.velocity);
  force.push_back({});
  mass.push_back(p.mass);
  restDensity.push_back(p.restDensity);
  density.push_back(p.restDensity);
  volume.push_back(p.restDensity > 0 ? p.mass / p.restDensity : 0);
  pressure.push_back(0);
  viscosity.push_back(p.viscosity);
  stiffness.push_back(p.stiffness);
  if (has(Attribute::InterfaceColour)) interfaceColour.push_back(p.interfaceColour);
  if (has(Attribute::SurfaceColour)) surfaceColour.push_back(p.surfaceColour);
  if (has(Attribute::Temperature)) temperature.push_back(p.temperature);
  if (has(Attribute::Dye)) dye.push_back(p.dye);
  // A newborn particle starts without pressure; the solves build it within the step.
  if (has(Attribute::DivergencePressure)) divergencePressure.push_back(0);
  if (has(Attribute::Latent)) latent.push_back(0);
}

void ParticleSet::permute(const std::vector<uint32_t>& order) {
  forEachArray([&order](const char*, auto& v) {
    std::remove_reference_t<decltype(v)> out(order.size());
    for (size_t i = 0; i < order.size(); ++i) out[i] = v[order[i]];
    v.swap(out);
  });
}

size_t ParticleSet::removeFlagged(const std::vector<uint8_t>& flags) {
  const size_t n = size();
  size_t kept = 0;
  for (size_t i = 0; i < n; ++i) kept += flags[i] ? 0 : 1;
  if (kept == n) return 0;
  forEachArray([&](const char*, auto& v) {
    size_t w = 0;
    for (size_t i = 0; i < n; ++i)
      if (!flags[i]) v[w++] = v[i];
    v.resize(w);
  });
  return n - kept;
}

size_t ParticleSet::memoryBytes() const {
  size_t bytes = 0;
  const_cast<ParticleSet*>(this)->forEachArray(
      [&bytes](const char*, const auto& v) { bytes += v.capacity() * sizeof(v[0]); });
  return bytes;
}

Real ParticleSet::largestCompression() const {
  return parallelMax(size(), [&](size_t i) { return density[i] / restDensity[i] - 1; });
}

}  // namespace mf
