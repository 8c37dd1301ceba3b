// Renormalising a level set to a true signed distance on its band (a grids-in, grids-out tool, as
// OpenVDB's tools are). particlesToSurface runs it on each body's filtered field.
#pragma once

#include <openvdb/openvdb.h>

namespace mf::surfacing {

/// Signed distance to the zero crossing on the active voxels of `grid` (a band around it), as
/// tools::sdfToSdf computes it: the voxels next to the crossing get its distance along the axes,
/// the others the Godunov upwind solution of |grad phi| = 1 (FastSweeping's update, in the same
/// float arithmetic). Instead of FastSweeping's eight diagonal sweeps, whose bookkeeping (a copy
/// of the band, and masks per leaf and diagonal slice for four directions) cost most of the
/// stage's memory at 1 M particles, the update runs in Jacobi passes over the voxels next to
/// those that changed in the pass before, until none changes: per leaf, in parallel, with a
/// result independent of the thread count. The same values as sdfToSdf to 1e-6 voxels on the
/// tests' shapes. Distances from `limit` up are not needed (the band is trimmed there): the
/// voxels beyond it keep +-FLT_MAX or a value at least `limit`, which cannot change the voxels
/// below it (an update reads only smaller neighbours).
void redistance(openvdb::FloatGrid& grid, float limit);

}  // namespace mf::surfacing
