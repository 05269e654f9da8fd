// A binary PLY mesh written in pieces.

#include "io/ply_mesh_stream.hpp"

#include <clustersurf/core/errors.hpp>

namespace clustersurf::io {

PlyMeshStream::PlyMeshStream(const std::filesystem::path& file, std::uint64_t vertices, std::uint64_t triangles,
                             bool normals, bool colors, const Eigen::Vector3d& origin, UpAxis up)
    : out_(file),
      vertices_(vertices),
      triangles_(triangles),
      normals_(normals && vertices > 0),
      colors_(colors && vertices > 0),
      double_(!origin.isZero()),
      origin_(origin) {
  out_.write(ply_header(vertices, triangles, true, double_, normals_, colors_, {}, up));
  buffer_.reserve(1 << 20);
}

void PlyMeshStream::flush_if_full() {
  if (buffer_.size() > (1u << 20) - 256) {
    out_.write(buffer_.data(), buffer_.size());
    buffer_.clear();
  }
}

void PlyMeshStream::add_vertices(const Points& positions, const Points& normals, const Colors& colors) {
  if (vertices_written_ + static_cast<std::uint64_t>(positions.rows()) > vertices_ || triangles_written_ > 0)
    throw IoError("PLY stream: more vertices than announced, or vertices after triangles");
  const auto put = [&](const auto& value) {
    const char* p = reinterpret_cast<const char*>(&value);
    buffer_.insert(buffer_.end(), p, p + sizeof(value));
  };
  const auto put_real = [&](double x) {
    if (double_)
      put(x);
    else
      put(static_cast<float>(x));
  };
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    for (int k = 0; k < 3; ++k) put_real(origin_(k) == 0 ? positions(i, k) : positions(i, k) + origin_(k));
    if (normals_)
      for (int k = 0; k < 3; ++k) put_real(normals(i, k));
    if (colors_)
      for (int k = 0; k < 3; ++k) put(colors(i, k));
    flush_if_full();
  }
  vertices_written_ += static_cast<std::uint64_t>(positions.rows());
}

void PlyMeshStream::add_triangles(const Triangles& triangles) {
  if (vertices_written_ != vertices_ || triangles_written_ + static_cast<std::uint64_t>(triangles.rows()) > triangles_)
    throw IoError("PLY stream: triangles before every vertex, or more than announced");
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    buffer_.push_back(3);
    for (int k = 0; k < 3; ++k) {
      const std::int32_t v = triangles(t, k);
      const char* p = reinterpret_cast<const char*>(&v);
      buffer_.insert(buffer_.end(), p, p + sizeof v);
    }
    flush_if_full();
  }
  triangles_written_ += static_cast<std::uint64_t>(triangles.rows());
}

void PlyMeshStream::commit() {
  if (vertices_written_ != vertices_ || triangles_written_ != triangles_)
    throw IoError("PLY stream: " + std::to_string(vertices_written_) + " of " + std::to_string(vertices_) +
                  " vertices and " + std::to_string(triangles_written_) + " of " + std::to_string(triangles_) +
                  " triangles written");
  out_.write(buffer_.data(), buffer_.size());
  out_.commit();
}

}  // namespace clustersurf::io
