// Vertex rings in compressed rows, built and summed in an order that does not depend on the
// vertices' numbering.

#include "mesh/vertex_rings.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <numbers>

namespace clustersurf::detail {

VertexRings edge_neighbors(const TriangleMesh& mesh) {
  const auto n = static_cast<std::size_t>(mesh.vertices.rows());
  // Each corner of a triangle gives its vertex the two others: counted, placed, then each
  // vertex's list sorted and its repeats dropped.
  std::vector<std::uint32_t> begin(n + 1, 0);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) begin[static_cast<std::size_t>(mesh.triangles(t, k)) + 1] += 2;
  for (std::size_t v = 0; v < n; ++v) begin[v + 1] += begin[v];
  std::vector<std::uint32_t> slots(n, 0), listed(begin.back());
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(mesh.triangles(t, k));
      listed[begin[v] + slots[v]++] = static_cast<std::uint32_t>(mesh.triangles(t, (k + 1) % 3));
      listed[begin[v] + slots[v]++] = static_cast<std::uint32_t>(mesh.triangles(t, (k + 2) % 3));
    }
  // Each ring in the order of its vertices' positions, not of their numbers: a tile of the same
  // surface, numbered otherwise, sums the same values in the same order.
  const auto before = [&](std::uint32_t x, std::uint32_t y) {
    const auto px = mesh.vertices.row(x), py = mesh.vertices.row(y);
    return std::lexicographical_compare(px.begin(), px.end(), py.begin(), py.end());
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      const auto first = listed.begin() + begin[v], last = listed.begin() + begin[v + 1];
      std::sort(first, last);
      slots[v] = static_cast<std::uint32_t>(std::unique(first, last) - first);
      std::sort(first, first + slots[v], before);
    }
  });
  VertexRings r;
  r.begin.assign(n + 1, 0);
  for (std::size_t v = 0; v < n; ++v) r.begin[v + 1] = r.begin[v] + slots[v];
  r.neighbors.resize(r.begin.back());
  for (std::size_t v = 0; v < n; ++v)
    std::copy_n(listed.begin() + begin[v], slots[v], r.neighbors.begin() + r.begin[v]);
  return r;
}

std::vector<double> ring_mean(const VertexRings& rings, std::vector<double> values, std::uint32_t rounds) {
  std::vector<double> next(values.size());
  for (std::uint32_t round = 0; round < rounds; ++round) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, values.size(), 4096), [&](const auto& range) {
      for (std::size_t v = range.begin(); v != range.end(); ++v) {
        double sum = values[v];
        for (std::uint32_t k = rings.begin[v]; k < rings.begin[v + 1]; ++k) sum += values[rings.neighbors[k]];
        next[v] = sum / static_cast<double>(1 + rings.begin[v + 1] - rings.begin[v]);
      }
    });
    values.swap(next);
  }
  return values;
}

double kernel_vertices(std::uint32_t rounds) {
  const int size = 2 * static_cast<int>(rounds) + 1, c = static_cast<int>(rounds);
  std::vector<double> k(static_cast<std::size_t>(size * size), 0.0), next(k.size());
  const auto at = [&](std::vector<double>& g, int q, int r) -> double& {
    return g[static_cast<std::size_t>(q * size + r)];
  };
  at(k, c, c) = 1;
  constexpr int kSteps[6][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, -1}, {-1, 1}};
  for (std::uint32_t round = 0; round < rounds; ++round) {
    for (int q = 0; q < size; ++q)
      for (int r = 0; r < size; ++r) {
        double sum = at(k, q, r);
        for (const auto& d : kSteps) {
          const int a = q + d[0], b = r + d[1];
          if (a >= 0 && a < size && b >= 0 && b < size) sum += at(k, a, b);
        }
        at(next, q, r) = sum / 7;
      }
    k.swap(next);
  }
  double sum = 0, squares = 0;
  for (const double x : k) sum += x, squares += x * x;
  return sum * sum / squares;
}

std::vector<double> vertex_areas(const TriangleMesh& mesh, const VertexRings& rings) {
  std::vector<double> area(static_cast<std::size_t>(mesh.vertices.rows()), 0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, area.size(), 4096), [&](const auto& range) {
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      double sum = 0;
      for (std::uint32_t k = rings.begin[v]; k < rings.begin[v + 1]; ++k)
        sum += (mesh.vertices.row(rings.neighbors[k]) - mesh.vertices.row(static_cast<Eigen::Index>(v))).squaredNorm();
      const std::uint32_t count = rings.begin[v + 1] - rings.begin[v];
      if (count > 0) area[v] = std::numbers::sqrt3 / 2 * sum / count;
    }
  });
  return area;
}

}  // namespace clustersurf::detail
