// What a finished (or stopped) simulation run should tell its user: counts that say the result
// may not be what the scene meant. The pipeline prints them after the summary.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace mf {

class Simulation;

/// Particles of each phase, index = phase.
std::vector<size_t> phaseCounts(const Simulation& sim);

/// Warnings for the run so far, given the counts per phase as seeded: wall clamps (particles
/// put back inside a container), watchdog retries (with the last one's reason), a peak compression over 10 %, a phase of which
/// over 1 % (of all it had, seeded and born) left the domain, a phase
/// down to less than half of what was seeded (boiled away, removed), no particle left.
std::vector<std::string> runWarnings(const Simulation& sim, const std::vector<size_t>& seeded);

}  // namespace mf
