#include "bodies.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_set>
#include <utility>

#include "sim/disjoint_sets.h"

namespace mf::surfacing {

namespace {

/// Particles sorted by cell of a cubic grid (a copy of the positions in that order, for the
/// neighbour searches below). Cell coordinates are kept modulo 2^21 per axis, so far-apart
/// cells may share a key: that only adds distance checks, which are exact.
struct CellIndex {
  static constexpr uint64_t kMask = (uint64_t(1) << 21) - 1;
  static uint64_t key(int64_t x, int64_t y, int64_t z) {
    return (uint64_t(z) & kMask) << 42 | (uint64_t(y) & kMask) << 21 | (uint64_t(x) & kMask);
  }
  std::vector<uint32_t> order;           // particle index of each sorted entry
  std::vector<openvdb::Vec3d> sorted;    // their positions
  std::vector<uint64_t> keys;            // each cell's key, ascending
  std::vector<std::array<int64_t, 3>> coords;  // a cell's coordinates (its first entry's)
  std::vector<uint32_t> start;           // each cell's first entry; one more at the end

  CellIndex(const std::vector<openvdb::Vec3d>& p, double size) {
    auto cellOf = [&](const openvdb::Vec3d& q) {
      return std::array<int64_t, 3>{int64_t(std::floor(q.x() / size)), int64_t(std::floor(q.y() / size)),
                                    int64_t(std::floor(q.z() / size))};
    };
    std::vector<std::pair<uint64_t, uint32_t>> keyed(p.size());
    for (size_t i = 0; i < p.size(); ++i) {
      const auto c = cellOf(p[i]);
      keyed[i] = {key(c[0], c[1], c[2]), uint32_t(i)};
    }
    std::sort(keyed.begin(), keyed.end());
    order.resize(p.size());
    sorted.resize(p.size());
    for (size_t i = 0; i < keyed.size(); ++i) {
      order[i] = keyed[i].second;
      sorted[i] = p[keyed[i].second];
      if (i == 0 || keyed[i].first != keyed[i - 1].first) {
        keys.push_back(keyed[i].first);
        coords.push_back(cellOf(sorted[i]));
        start.push_back(uint32_t(i));
      }
    }
    start.push_back(uint32_t(p.size()));
  }
  /// Index of the cell at offset d from cell c, or -1 if empty.
  long neighbour(size_t c, int dx, int dy, int dz) const {
    const uint64_t k = key(coords[c][0] + dx, coords[c][1] + dy, coords[c][2] + dz);
    const auto it = std::lower_bound(keys.begin(), keys.end(), k);
    return it != keys.end() && *it == k ? long(it - keys.begin()) : -1;
  }
  /// Calls f(i, j) (sorted entries) for every pair closer than `range` (the cell size at most),
  /// each pair once.
  template <class F>
  void forEachPairWithin(double range, F&& f) const {
    const double range2 = range * range;
    // The 13 neighbours after a cell in (z, y, x) order: each pair of cells once. Their keys
    // grow with the cell's, so each is found by a cursor that only moves forward (or, where the
    // coordinates wrap, by a search).
    std::array<std::array<int, 3>, 13> offsets;
    std::array<size_t, 13> cursor{};
    for (int dz = 0, o = 0; dz <= 1; ++dz)
      for (int dy = dz ? -1 : 0; dy <= 1; ++dy)
        for (int dx = (dz || dy) ? -1 : 1; dx <= 1; ++dx) offsets[size_t(o++)] = {dx, dy, dz};
    for (size_t c = 0; c + 1 < start.size(); ++c) {
      const uint32_t b0 = start[c], e0 = start[c + 1];
      for (uint32_t i = b0; i < e0; ++i)
        for (uint32_t j = i + 1; j < e0; ++j)
          if ((sorted[i] - sorted[j]).lengthSqr() < range2) f(i, j);
      for (size_t o = 0; o < offsets.size(); ++o) {
        const auto& d = offsets[o];
        const uint64_t k = key(coords[c][0] + d[0], coords[c][1] + d[1], coords[c][2] + d[2]);
        size_t& n = cursor[o];
        if (n > 0 && keys[n - 1] >= k) n = size_t(std::lower_bound(keys.begin(), keys.end(), k) - keys.begin());
        while (n < keys.size() && keys[n] < k) ++n;  // now the first key >= k
        if (n == keys.size() || keys[n] != k || n == c) continue;
        for (uint32_t i = b0; i < e0; ++i)
          for (uint32_t j = start[n]; j < start[n + 1]; ++j)
            if ((sorted[i] - sorted[j]).lengthSqr() < range2) f(i, j);
      }
    }
  }
};

}  // namespace

uint32_t findBodies(const std::vector<openvdb::Vec3d>& p, double link, std::vector<uint32_t>& body) {
  const CellIndex index(p, link);
  mf::DisjointSets sets(p.size());  // over sorted entries
  index.forEachPairWithin(link, [&](uint32_t a, uint32_t b) { sets.unite(a, b); });
  std::vector<uint32_t> sortedOf(p.size()), label(p.size(), ~0u);
  for (size_t i = 0; i < p.size(); ++i) sortedOf[index.order[i]] = uint32_t(i);
  body.resize(p.size());
  uint32_t count = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    uint32_t& l = label[sets.root(sortedOf[i])];
    if (l == ~0u) l = count++;
    body[i] = l;
  }
  return count;
}

uint32_t colourBodies(const std::vector<openvdb::Vec3d>& p, const std::vector<uint32_t>& body, uint32_t bodies,
                      double near, std::vector<uint32_t>& colour) {
  colour.assign(bodies, 0);
  if (bodies <= 1) return 1;
  const CellIndex index(p, near);
  // Each cell's entries grouped by body: (body, first, end) into `entries`.
  const size_t cells = index.keys.size();
  std::vector<uint32_t> entries(p.size());
  std::vector<std::array<uint32_t, 3>> groups;
  std::vector<uint32_t> cellGroups(cells + 1);
  for (size_t c = 0; c < cells; ++c) {
    const uint32_t b0 = index.start[c], e0 = index.start[c + 1];
    for (uint32_t i = b0; i < e0; ++i) entries[i] = i;
    std::stable_sort(entries.begin() + b0, entries.begin() + e0,
                     [&](uint32_t x, uint32_t y) { return body[index.order[x]] < body[index.order[y]]; });
    cellGroups[c] = uint32_t(groups.size());
    for (uint32_t i = b0; i < e0; ++i)
      if (i == b0 || body[index.order[entries[i]]] != groups.back()[0]) groups.push_back({body[index.order[entries[i]]], i, i + 1});
      else groups.back()[2] = i + 1;
  }
  cellGroups[cells] = uint32_t(groups.size());
  // An edge between two bodies with particles closer than `near`: checked group against group
  // of neighbouring cells, once per pair of bodies.
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  std::unordered_set<uint64_t> known;
  const double near2 = near * near;
  auto check = [&](size_t c, size_t n) {
    for (uint32_t g = cellGroups[c]; g < cellGroups[c + 1]; ++g)
      for (uint32_t h = (c == n ? g + 1 : cellGroups[n]); h < cellGroups[n + 1]; ++h) {
        const uint32_t x = std::min(groups[g][0], groups[h][0]), y = std::max(groups[g][0], groups[h][0]);
        const uint64_t id = uint64_t(x) << 32 | y;
        if (known.count(id)) continue;
        bool close = false;
        for (uint32_t i = groups[g][1]; i < groups[g][2] && !close; ++i)
          for (uint32_t j = groups[h][1]; j < groups[h][2] && !close; ++j)
            close = (index.sorted[entries[i]] - index.sorted[entries[j]]).lengthSqr() < near2;
        if (close) known.insert(id), edges.emplace_back(x, y);
      }
  };
  for (size_t c = 0; c < cells; ++c) {
    check(c, c);
    for (int dz = 0; dz <= 1; ++dz)
      for (int dy = dz ? -1 : 0; dy <= 1; ++dy)
        for (int dx = (dz || dy) ? -1 : 1; dx <= 1; ++dx) {
          const long n = index.neighbour(c, dx, dy, dz);
          if (n >= 0 && size_t(n) != c) check(c, size_t(n));
        }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<std::vector<uint32_t>> adjacent(bodies);
  for (const auto& [a, b] : edges) adjacent[a].push_back(b), adjacent[b].push_back(a);
  std::vector<uint32_t> size(bodies, 0);
  for (uint32_t b : body) ++size[b];
  std::vector<uint32_t> byDecreasingSize(bodies);
  for (uint32_t b = 0; b < bodies; ++b) byDecreasingSize[b] = b;
  std::stable_sort(byDecreasingSize.begin(), byDecreasingSize.end(), [&](uint32_t a, uint32_t b) { return size[a] > size[b]; });
  constexpr uint32_t kNone = ~0u;
  std::fill(colour.begin(), colour.end(), kNone);
  uint32_t colours = 0;
  std::vector<char> taken;
  for (uint32_t b : byDecreasingSize) {
    taken.assign(colours + 1, 0);
    for (uint32_t n : adjacent[b])
      if (colour[n] != kNone) taken[colour[n]] = 1;
    uint32_t c = 0;
    while (taken[c]) ++c;
    colour[b] = c;
    colours = std::max(colours, c + 1);
  }
  return colours;
}

}  // namespace mf::surfacing
