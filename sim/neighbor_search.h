// Uniform-grid neighbour search with cell size = support radius h. Particles are ordered by the
// Z-order (Morton) key of their cell, so that neighbours in space are neighbours in memory; the
// 27 cells around a particle's cell hold every particle within h.
//
// Deterministic by construction: the sort key is (cell key, particle index), a total order, so
// every sort gives the same permutation; neighbour lists are written in a fixed order (cell key,
// then particle index) whatever the number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "periodic.h"
#include "vec3.h"

namespace mf {

/// Compressed rows of neighbour indices: row i is indices[offsets[i] .. offsets[i+1]).
struct NeighborLists {
  std::vector<uint64_t> offsets;  // size n+1
  std::vector<uint32_t> indices;

  size_t rows() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  uint64_t begin(size_t i) const { return offsets[i]; }
  uint64_t end(size_t i) const { return offsets[i + 1]; }
  size_t count(size_t i) const { return size_t(offsets[i + 1] - offsets[i]); }
  size_t totalPairs() const { return indices.size(); }
};

/// Points binned into cells of size h, sorted by the Morton key of the cell.
class CellGrid {
 public:
  /// Bins n points; `origin` is the lower corner of the grid (points below it are clamped
  /// into the first cell layer, which only matters for points about to be removed).
  void build(const Vec3* points, size_t n, const Vec3& origin, Real cellSize);


  /// Point indices in cell order.
  const std::vector<uint32_t>& sortedIndices() const { return sorted_; }
  size_t cellCount() const { return cellKeys_.size(); }
  Real cellSize() const { return cellSize_; }

  /// For each point, its list of points of `other` (or of this grid) within `radius` (<= the
  /// cell size), excluding itself when other == this. Both grids must have been built from the
  /// points passed here (positions are read from the grids' sorted copies). Rows follow the point index; inside a row,
  /// neighbours come in a fixed order (the 27 cells in z, y, x order, then cell order).
  /// With periodic axes, points within `radius` of a periodic face also look around their
  /// images one period across (after the direct cells, images in a fixed order); the period
  /// must exceed 2 radius, so each neighbour is found once.
  void findNeighbors(const CellGrid& other, Real radius, bool excludeSelf, NeighborLists& out,
                     const PeriodicDomain& periodic = {}) const;

  /// Cell coordinates of a position (clamped to the grid's non-negative range).
  void cellOf(const Vec3& p, int32_t c[3]) const;

 private:
  int64_t findCell(int32_t x, int32_t y, int32_t z) const;  // index into cellKeys_, or -1

  Vec3 origin_;
  Real cellSize_ = 1;
  std::vector<uint32_t> sorted_;      // point indices in (key, index) order
  std::vector<Vec3> sortedPoints_;    // the points in that order: candidate scans read memory linearly
  std::vector<uint64_t> cellKeys_;    // sorted unique Morton keys
  std::vector<uint32_t> cellStart_;   // cellStart_[c] .. cellStart_[c+1] in sorted_
  std::vector<int32_t> cellCoord_;    // 3 ints per cell
  // Where the occupied cells' bounding box is small, a dense table of cell index + 1 (0: empty)
  // answers findCell in one read instead of a binary search over the keys.
  std::vector<uint32_t> dense_;
  int32_t denseLo_[3] = {0, 0, 0}, denseDim_[3] = {0, 0, 0};
};

/// Morton key of non-negative cell coordinates (21 bits each).
uint64_t mortonKey(uint32_t x, uint32_t y, uint32_t z);

}  // namespace mf
