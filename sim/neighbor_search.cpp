#include "neighbor_search.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>

namespace mf {

namespace {

uint64_t spreadBits(uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

constexpr int32_t kMaxCoord = (1 << 21) - 1;

struct KeyIndex {
  uint64_t key;
  uint32_t index;
  bool operator<(const KeyIndex& o) const { return key < o.key || (key == o.key && index < o.index); }
};

// Fixed work-block size: block boundaries never depend on the thread count.
constexpr size_t kCellsPerBlock = 64;

// A block's neighbour indices. Each particle reserves room for all its candidates and keeps the
// few within reach; growing by doubling without zero-filling leaves the room it never writes
// untouched (a std::vector would clear every particle's candidates first).
struct IndexBuffer {
  std::unique_ptr<uint32_t[]> data;
  size_t used = 0, capacity = 0;
  uint32_t* roomFor(size_t extra) {
    if (used + extra > capacity) {
      const size_t grown = std::max(used + extra, 2 * capacity);
      std::unique_ptr<uint32_t[]> bigger(new uint32_t[grown]);
      std::copy_n(data.get(), used, bigger.get());
      data = std::move(bigger);
      capacity = grown;
    }
    return data.get() + used;
  }
};

}  // namespace

uint64_t mortonKey(uint32_t x, uint32_t y, uint32_t z) {
  return spreadBits(x) | (spreadBits(y) << 1) | (spreadBits(z) << 2);
}

void CellGrid::cellOf(const Vec3& p, int32_t c[3]) const {
  for (int a = 0; a < 3; ++a) {
    const Real f = std::floor((p[a] - origin_[a]) / cellSize_);
    // NaN compares false everywhere: it lands in cell 0 and the watchdog reports it.
    c[a] = f > 0 ? (f < kMaxCoord ? int32_t(f) : kMaxCoord) : 0;
  }
}

void CellGrid::build(const Vec3* points, size_t n, const Vec3& origin, Real cellSize) {
  origin_ = origin;
  cellSize_ = cellSize;
  std::vector<KeyIndex> keys(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      int32_t c[3];
      cellOf(points[i], c);
      keys[i] = {mortonKey(c[0], c[1], c[2]), uint32_t(i)};
    }
  });
  tbb::parallel_sort(keys.begin(), keys.end());

  sorted_.resize(n);
  sortedPoints_.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p != r.end(); ++p) sortedPoints_[p] = points[keys[p].index];
  });
  cellKeys_.clear();
  cellStart_.clear();
  cellCoord_.clear();
  for (size_t p = 0; p < n; ++p) {
    sorted_[p] = keys[p].index;
    if (p == 0 || keys[p].key != keys[p - 1].key) {
      cellKeys_.push_back(keys[p].key);
      cellStart_.push_back(uint32_t(p));
      int32_t c[3];
      cellOf(points[keys[p].index], c);
      cellCoord_.insert(cellCoord_.end(), c, c + 3);
    }
  }
  cellStart_.push_back(uint32_t(n));

  dense_.clear();
  const size_t nCells = cellKeys_.size();
  if (nCells == 0) return;
  int32_t lo[3] = {kMaxCoord, kMaxCoord, kMaxCoord}, hi[3] = {0, 0, 0};
  for (size_t c = 0; c < nCells; ++c)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], cellCoord_[3 * c + a]);
      hi[a] = std::max(hi[a], cellCoord_[3 * c + a]);
    }
  const uint64_t volume = uint64_t(hi[0] - lo[0] + 1) * uint64_t(hi[1] - lo[1] + 1) * uint64_t(hi[2] - lo[2] + 1);
  // Clearing the table costs its volume each build: only where that is of the order of the cells.
  if (volume > std::max<uint64_t>(uint64_t(1) << 20, 16 * uint64_t(nCells))) return;
  for (int a = 0; a < 3; ++a) {
    denseLo_[a] = lo[a];
    denseDim_[a] = hi[a] - lo[a] + 1;
  }
  dense_.assign(volume, 0);
  for (size_t c = 0; c < nCells; ++c) {
    const int32_t* cc = &cellCoord_[3 * c];
    dense_[(size_t(cc[2] - lo[2]) * size_t(denseDim_[1]) + size_t(cc[1] - lo[1])) * size_t(denseDim_[0]) + size_t(cc[0] - lo[0])] =
        uint32_t(c + 1);
  }
}

int64_t CellGrid::findCell(int32_t x, int32_t y, int32_t z) const {
  if (!dense_.empty()) {
    const int32_t u = x - denseLo_[0], v = y - denseLo_[1], w = z - denseLo_[2];
    if (u < 0 || v < 0 || w < 0 || u >= denseDim_[0] || v >= denseDim_[1] || w >= denseDim_[2]) return -1;
    return int64_t(dense_[(size_t(w) * size_t(denseDim_[1]) + size_t(v)) * size_t(denseDim_[0]) + size_t(u)]) - 1;
  }
  const uint64_t key = mortonKey(uint32_t(x), uint32_t(y), uint32_t(z));
  auto it = std::lower_bound(cellKeys_.begin(), cellKeys_.end(), key);
  if (it == cellKeys_.end() || *it != key) return -1;
  return it - cellKeys_.begin();
}

void CellGrid::findNeighbors(const CellGrid& other, Real radius, bool excludeSelf, NeighborLists& out,
                             const PeriodicDomain& periodic) const {
  const size_t nPoints = sorted_.size();
  const size_t nCells = cellKeys_.size();
  const size_t nBlocks = (nCells + kCellsPerBlock - 1) / kCellsPerBlock;
  const Real r2max = radius * radius;
  // The other grid may have a different origin: neighbour cells are looked up by position.
  const bool sameLayout = other.origin_ == origin_ && other.cellSize_ == cellSize_;

  std::vector<IndexBuffer> blockIndices(nBlocks);
  std::vector<uint32_t> counts(nPoints + 1, 0);

  tbb::parallel_for(size_t(0), nBlocks, [&](size_t b) {
    IndexBuffer& buf = blockIndices[b];
    const size_t c0 = b * kCellsPerBlock, c1 = std::min(nCells, c0 + kCellsPerBlock);
    // Up to 27 images (the cell itself, and one period up or down on up to three axes: a cell
    // can be near both faces of a period under 2 radius + its size). A query box
    // aligned with the other grid's cells needs its 27 neighbours; one that is not (another
    // origin, or an image shifted by a period) overlaps up to 4 cells per axis.
    constexpr int kMaxRanges = 64 * 27;
    uint32_t ranges[kMaxRanges][2];
    Vec3 boxLo[kMaxRanges];  // lower corner of each neighbour cell, to skip cells out of reach
    int rangeImage[kMaxRanges];
    Vec3 imageShift[27];
    const Real cs = other.cellSize_;
    const auto addCell = [&](int& nr, int32_t x, int32_t y, int32_t z, int image) {
      if (x < 0 || y < 0 || z < 0 || x > kMaxCoord || y > kMaxCoord || z > kMaxCoord) return;
      const int64_t oc = other.findCell(x, y, z);
      if (oc < 0) return;
      ranges[nr][0] = other.cellStart_[oc];
      ranges[nr][1] = other.cellStart_[oc + 1];
      boxLo[nr] = other.origin_ + Vec3(x, y, z) * cs;
      rangeImage[nr] = image;
      ++nr;
    };
    // The other grid's cells that meet [lo - radius, lo + cellSize_ + radius) on every axis.
    const auto addOverlapped = [&](int& nr, const Vec3& lo, int image) {
      int32_t first[3], last[3];
      for (int a = 0; a < 3; ++a) {
        const Real f = std::floor((lo[a] - radius - other.origin_[a]) / cs);
        const Real l = std::ceil((lo[a] + cellSize_ + radius - other.origin_[a]) / cs) - 1;
        first[a] = f < -1 ? -1 : (f > kMaxCoord + 1 ? kMaxCoord + 1 : int32_t(f));
        last[a] = l < -1 ? -1 : (l > kMaxCoord + 1 ? kMaxCoord + 1 : int32_t(l));
        last[a] = std::min(last[a], first[a] + 3);
      }
      for (int32_t z = first[2]; z <= last[2]; ++z)
        for (int32_t y = first[1]; y <= last[1]; ++y)
          for (int32_t x = first[0]; x <= last[0]; ++x) addCell(nr, x, y, z, image);
    };
    for (size_t c = c0; c < c1; ++c) {
      int nr = 0;
      const int32_t base[3] = {cellCoord_[3 * c], cellCoord_[3 * c + 1], cellCoord_[3 * c + 2]};
      const Vec3 cellLo = origin_ + Vec3(base[0], base[1], base[2]) * cellSize_;
      imageShift[0] = Vec3();
      if (sameLayout) {
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) addCell(nr, base[0] + dx, base[1] + dy, base[2] + dz, 0);
      } else {
        addOverlapped(nr, cellLo, 0);
      }
      int nImages = 1;
      const auto addImage = [&](const Vec3& shift) {
        imageShift[nImages] = shift;
        addOverlapped(nr, cellLo + shift, nImages);
        ++nImages;
      };
      if (periodic.any())
        periodic.forEachImage(cellLo, cellLo + Vec3(cellSize_, cellSize_, cellSize_), Vec3(radius, radius, radius), addImage);
      const Vec3* xs = other.sortedPoints_.data();
      const uint32_t* js = other.sorted_.data();
      // Room for every candidate of the cell's particles, so that the scan below can write each
      // one and advance only past those within reach (no branch to mispredict).
      size_t candidates = 0;
      for (int r = 0; r < nr; ++r) candidates += ranges[r][1] - ranges[r][0];
      for (uint32_t p = cellStart_[c]; p < cellStart_[c + 1]; ++p) {
        const uint32_t i = sorted_[p], skip = excludeSelf ? i : UINT32_MAX;  // no point has index UINT32_MAX
        uint32_t* out = buf.roomFor(candidates);
        size_t found = 0;
        for (int r = 0; r < nr; ++r) {
          const int image = rangeImage[r];
          const Vec3 xi = image == 0 ? sortedPoints_[p] : sortedPoints_[p] + imageShift[image];
          // Distance from xi to the cell's box: a cell entirely beyond the radius is skipped
          // (about a quarter of the 27 for a radius equal to the cell size).
          Real d2 = 0;
          for (int a = 0; a < 3; ++a) {
            const Real lo = boxLo[r][a], v = xi[a];
            const Real d = v < lo ? lo - v : (v > lo + cs ? v - lo - cs : 0);
            d2 += d * d;
          }
          if (d2 >= r2max) continue;
          for (uint32_t q = ranges[r][0]; q < ranges[r][1]; ++q) {
            const Vec3 d = xi - xs[q];
            const uint32_t j = js[q];
            out[found] = j;
            found += size_t((lengthSquared(d) < r2max) & (j != skip));
          }
        }
        buf.used += found;
        counts[i] = uint32_t(found);
      }
    }
  });

  out.offsets.resize(nPoints + 1);
  out.offsets[0] = 0;
  for (size_t i = 0; i < nPoints; ++i) out.offsets[i + 1] = out.offsets[i] + counts[i];
  out.indices.resize(out.offsets[nPoints]);

  tbb::parallel_for(size_t(0), nBlocks, [&](size_t b) {
    const uint32_t* buf = blockIndices[b].data.get();
    const size_t c0 = b * kCellsPerBlock, c1 = std::min(nCells, c0 + kCellsPerBlock);
    size_t k = 0;
    for (size_t c = c0; c < c1; ++c)
      for (uint32_t p = cellStart_[c]; p < cellStart_[c + 1]; ++p) {
        const uint32_t i = sorted_[p];
        std::copy_n(buf + k, counts[i], out.indices.begin() + out.offsets[i]);
        k += counts[i];
      }
  });
}

}  // namespace mf
