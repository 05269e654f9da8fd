// Vertices offset by the mean sag of their triangles' chords under the smooth surface.

#include "mesh/chord_sag.hpp"
#include "mesh/vertex_triangles.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace clustersurf::detail {

double offset_chord_sag(TriangleMesh& mesh, std::span<const float> fixed) {
  const auto n = static_cast<std::size_t>(mesh.vertices.rows());
  if (n == 0 || mesh.normals.rows() != mesh.vertices.rows()) return 0;
  const VertexTriangles star(mesh.triangles, n);
  const double min_cosine = std::cos(kMaxSagTurn);
  const Points& x = mesh.vertices;
  const Points& normal = mesh.normals;
  std::vector<double> offset(n, 0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    std::vector<std::pair<double, double>> terms;  // (area × weighted sag, area) per triangle
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      if (v < fixed.size() && fixed[v] > 0) continue;
      terms.clear();
      bool smooth = true;
      for (const std::uint32_t triangle : star.of(static_cast<std::uint32_t>(v))) {
        if (!smooth) break;
        const auto t = static_cast<Eigen::Index>(triangle);
        // The triangle's other corners, b and c, whichever their order in it.
        std::array<Eigen::Index, 2> other{};
        int found = 0;
        for (int k = 0; k < 3; ++k)
          if (static_cast<std::size_t>(mesh.triangles(t, k)) != v)
            other[static_cast<std::size_t>(found++)] = mesh.triangles(t, k);
        if (found != 2) continue;  // degenerate: a corner repeated
        const auto a = static_cast<Eigen::Index>(v);
        const auto [b, c] = other;
        const auto q = [&](Eigen::Index i, Eigen::Index j) {
          return (normal.row(i) - normal.row(j)).dot(x.row(i) - x.row(j));
        };
        smooth = normal.row(a).dot(normal.row(b)) >= min_cosine && normal.row(b).dot(normal.row(c)) >= min_cosine &&
                 normal.row(c).dot(normal.row(a)) >= min_cosine;
        const double area = 0.5 * (x.row(b) - x.row(a)).cross(x.row(c) - x.row(a)).norm();
        // ∫ λa (gap) / ∫ λa over the triangle: (A/60 q_bc + A/30 (q_ab + q_ac)) / 2 over A/3.
        terms.emplace_back(area * (q(b, c) + 2 * (q(a, b) + q(a, c))) / 40, area);
      }
      if (!smooth || terms.empty()) continue;
      std::sort(terms.begin(), terms.end());
      double sag = 0, area = 0;
      for (const auto& [s, a] : terms) sag += s, area += a;
      if (area > 0) offset[v] = sag / area;
    }
  });
  double total = 0;
  for (std::size_t v = 0; v < n; ++v) {
    mesh.vertices.row(static_cast<Eigen::Index>(v)) += offset[v] * normal.row(static_cast<Eigen::Index>(v));
    total += std::abs(offset[v]);
  }
  return total / static_cast<double>(n);
}

}  // namespace clustersurf::detail
