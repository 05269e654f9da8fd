// Sub-meshes that keep every per-vertex quantity of the vertices they keep.

#include "mesh/mesh_subset.hpp"

#include <tbb/parallel_for.h>

#include <atomic>

namespace clustersurf::detail {

namespace {

/// The rows of `from` listed in `rows`, gathered in parallel.
template <class Matrix>
Matrix gathered(const Matrix& from, const std::vector<Eigen::Index>& rows) {
  Matrix out(static_cast<Eigen::Index>(rows.size()), from.cols());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rows.size(), 8192), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) out.row(static_cast<Eigen::Index>(i)) = from.row(rows[i]);
  });
  return out;
}

}  // namespace

TriangleMesh with_new_triangles(const TriangleMesh& mesh, const Triangles& triangles) {
  const Eigen::Index nv = mesh.vertices.rows();
  // Each used vertex marked, then numbered in its order; every step but the numbering runs in
  // parallel (the marks are one value, written with relaxed atomics).
  std::vector<std::int32_t> remap(static_cast<std::size_t>(nv), -1);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, triangles.rows(), 16384), [&](const auto& r) {
    for (Eigen::Index t = r.begin(); t != r.end(); ++t)
      for (int k = 0; k < 3; ++k)
        std::atomic_ref<std::int32_t>(remap[static_cast<std::size_t>(triangles(t, k))])
            .store(0, std::memory_order_relaxed);
  });
  std::vector<Eigen::Index> rows;
  for (Eigen::Index v = 0; v < nv; ++v)
    if (remap[static_cast<std::size_t>(v)] == 0)
      remap[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(rows.size()), rows.push_back(v);
  TriangleMesh out;
  out.origin = mesh.origin;
  out.up = mesh.up;
  out.vertices = gathered(mesh.vertices, rows);
  if (mesh.normals.rows() == nv) out.normals = gathered(mesh.normals, rows);
  if (mesh.colors.rows() == nv) out.colors = gathered(mesh.colors, rows);
  for (const PointAttribute& a : mesh.attributes)
    if (a.values.size() == nv) out.attributes.push_back({a.name, gathered(a.values, rows)});
  out.triangles.resize(triangles.rows(), 3);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, triangles.rows(), 16384), [&](const auto& r) {
    for (Eigen::Index t = r.begin(); t != r.end(); ++t)
      for (int k = 0; k < 3; ++k) out.triangles(t, k) = remap[static_cast<std::size_t>(triangles(t, k))];
  });
  return out;
}

TriangleMesh without_unused_vertices(const TriangleMesh& mesh) { return with_new_triangles(mesh, mesh.triangles); }

TriangleMesh with_triangles(const TriangleMesh& mesh, const std::vector<std::uint8_t>& keep) {
  std::vector<Eigen::Index> kept;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    if (keep[static_cast<std::size_t>(t)]) kept.push_back(t);
  return with_new_triangles(mesh, mesh.triangles(kept, Eigen::all));
}

}  // namespace clustersurf::detail
