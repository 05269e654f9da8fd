// Each vertex's triangles, by counting and placing.

#include "mesh/vertex_triangles.hpp"

#include <numeric>

namespace clustersurf::detail {

VertexTriangles::VertexTriangles(const Triangles& tris, std::size_t vertices) : begin(vertices + 1, 0) {
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) ++begin[static_cast<std::size_t>(tris(t, k)) + 1];
  std::partial_sum(begin.begin(), begin.end(), begin.begin());
  triangles.resize(begin.back());
  std::vector<std::uint32_t> next(begin.begin(), begin.end() - 1);
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) triangles[next[static_cast<std::size_t>(tris(t, k))]++] = static_cast<std::uint32_t>(t);
}

}  // namespace clustersurf::detail
