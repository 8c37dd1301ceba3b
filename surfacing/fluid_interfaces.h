// Closes the film of nothing between two fluids that touch. Each fluid is surfaced on its own,
// and where its particles stand a little more than a spacing from another fluid's (density
// contrast keeps the phases apart), the two zero crossings stop short of each other: a renderer
// then sees two interfaces with air between them (a grey or bright film). Where the fluids
// together are fluid (inside the level set of all their particles), each fluid reaches to the
// midway surface between its own and the nearest other's, as Losasso et al. (2006) split a gap
// between level sets, and `overlap` beyond it, so that the renderer's priorities pick one
// interface there.
#pragma once

#include <openvdb/openvdb.h>

#include <vector>

namespace mf::surfacing {

/// The overlap surfaceFrame uses, in voxels: half a voxel either side of the midway surface
/// keeps the two meshes' zero crossings (each placed to a small fraction of a voxel) from
/// leaving a sliver between them, and moves the drawn interface by at most half a voxel.
constexpr double kInterfaceOverlapVoxels = 0.5;

/// Whether any two of the level sets' narrow bands share a voxel (only then can a gap between
/// them be closed): the united level set is worth making.
bool fluidBandsTouch(const std::vector<openvdb::FloatGrid::Ptr>& levelSets);

/// @brief Fills the gaps between fluids inside their united level set.
/// @param levelSets  one level set per fluid, one transform, narrow bands (null or empty: skipped)
/// @param united     the level set of all those fluids' particles surfaced together
/// @param overlap    how far (world units) each fluid reaches past the midway surface
/// @return how many voxels changed sign, over all fluids
/// @details On each voxel outside fluid a and within another fluid's band, with b the nearest
/// other fluid, the distance becomes min(phi_a, max(phi_united, d - o)), d = (phi_a - phi_b) /
/// |grad phi_a - grad phi_b| the signed distance to the midway surface phi_a = phi_b ((phi_a -
/// phi_b) / 2 across a gap the two surfaces face), o = min(overlap, -phi_united): the overlap
/// tapers to nothing at the united surface, where two fluids would otherwise share its zero
/// crossing. A fluid thus only grows, only inside the united level set, only near another
/// fluid, and only to the middle of a gap plus `overlap`. Its band is widened by a voxel first,
/// so that it still reaches three voxels beyond a surface moved by up to one. The result
/// depends only on the inputs, not on their order or the thread count.
size_t closeFluidInterfaces(std::vector<openvdb::FloatGrid::Ptr>& levelSets, const openvdb::FloatGrid& united,
                            float overlap);

}  // namespace mf::surfacing
