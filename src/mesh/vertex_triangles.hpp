#pragma once
// Each vertex's triangles of a triangle mesh.

#include <clustersurf/core/point_cloud.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace clustersurf::detail {

/// Each vertex's triangles, in compressed rows, in the triangles' order.
struct VertexTriangles {
  std::vector<std::uint32_t> begin, triangles;
  VertexTriangles(const Triangles& tris, std::size_t vertices);
  std::span<const std::uint32_t> of(std::uint32_t v) const {
    return {triangles.data() + begin[v], begin[v + 1] - begin[v]};
  }
};

}  // namespace clustersurf::detail
