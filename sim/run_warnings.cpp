#include "run_warnings.h"

#include <fmt/format.h>

#include "simulation.h"

namespace mf {

std::vector<size_t> phaseCounts(const Simulation& sim) {
  std::vector<size_t> n(sim.scene().phases.size(), 0);
  for (uint16_t p : sim.particles().phase)
    if (p < n.size()) ++n[p];
  return n;
}

std::vector<std::string> runWarnings(const Simulation& sim, const std::vector<size_t>& seeded) {
  std::vector<std::string> w;
  const SimulationCounters& c = sim.counters();
  const Scene& scene = sim.scene();
  if (c.wallClamps > 0)
    w.push_back(fmt::format(
        "{} wall clamps: particles crossed a container wall and were put back on it (splashes reaching a wall with no "
        "pressure to stop them{})",
        c.wallClamps,
        scene.solver.pressure == PressureSolverChoice::WCSPH ? "; the implicit solver's walls need none: solver.pressure = \"dfsph\"" : ""));
  if (c.retries > 0) w.push_back(fmt::format("{} {} retried with a smaller dt; the last at {}", c.retries, c.retries == 1 ? "step was" : "steps were", sim.lastRetry()));
  if (c.maxDensityError > 0.1)
    w.push_back(fmt::format("the most compressed particle reached {:.1f} % (over 10 %: the volume is not kept there; {})",
                            100 * c.maxDensityError,
                            scene.solver.pressure == PressureSolverChoice::WCSPH ? "raise the phases' stiffness, or use solver.pressure = \"dfsph\""
                                                                                 : "lower solver.max_compression or solver.cfl"));
  // Per phase, against all it ever had (seeded and born): flames an emitter makes and pushes out
  // are named as flames, not counted against the water.
  const auto& left = sim.leftDomainByPhase();
  const auto& born = sim.bornByPhase();
  for (size_t p = 0; p < left.size() && p < seeded.size(); ++p) {
    const uint64_t had = seeded[p] + born[p];
    if (had > 0 && double(left[p]) > 0.01 * double(had))
      w.push_back(fmt::format("{} {} particles ({:.1f} % of the {} it had, seeded and born) left the domain and were removed: is "
                              "scene.domain_min/max too small?",
                              left[p], scene.phases[p].name, 100.0 * double(left[p]) / double(had), had));
  }
  const std::vector<size_t> now = phaseCounts(sim);
  for (size_t p = 0; p < seeded.size() && p < now.size(); ++p)
    if (seeded[p] > 0 && 2 * now[p] < seeded[p])
      w.push_back(fmt::format("phase \"{}\" is down to {} particles, {:.0f} % of the {} seeded (turned into another phase, "
                              "removed by a sink or lost)",
                              scene.phases[p].name, now[p], 100.0 * double(now[p]) / double(seeded[p]), seeded[p]));
  if (sim.particles().size() == 0) w.push_back("no particle is left: every frame from here on is empty");
  return w;
}

}  // namespace mf
