// Each format's blocks of a PointStream: XYZ and PTX lines, LAS and PLY records, E57's
// decoded points, PCD records.

#include "io/point_stream_impl.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace clustersurf {

using detail::non_finite_point;

/// The error for point `index` (0-based), found at `where`, that has `what` (a non-finite value).
InputError detail::non_finite_point(const std::filesystem::path& file, const FileLocation& where, std::uint64_t index,
                                    const std::string& what) {
  return InputError(
      file, where,
      "point " + std::to_string(index) + " (0-based) has " + what + "; use the option to drop such points");
}

std::uint16_t PointStream::Impl::pcd_color_maximum() {
  const io::pcd::Roles& r = pcd_layout->roles;
  std::uint16_t top = 0;
  while (pcd->next()) {
    if (std::isnan(pcd->value(r.position[0])) || std::isnan(pcd->value(r.position[1])) ||
        std::isnan(pcd->value(r.position[2])))
      continue;  // no point
    for (int k = 0; k < 3; ++k) top = std::max(top, io::pcd::wide_channel(pcd->value(r.rgb[k])));
  }
  pcd->rewind();
  mapped->release(0, mapped->view().size());
  return top;
}

void PointStream::Impl::read_xyz(Eigen::Index n, PointCloud& block) {
  const int normals = xyz_layout.normals, rgb = xyz_layout.colors;
  block.positions.resize(n, 3);
  if (normals >= 0) block.normals.resize(n, 3);
  if (rgb >= 0) block.colors.resize(n, 3);
  std::array<double, io::XyzLines::kMaxColumns> v{};
  const auto finite = [&](int from) {
    return std::all_of(v.begin() + from, v.begin() + from + 3, [](double x) { return std::isfinite(x); });
  };
  Eigen::Index kept = 0;
  for (Eigen::Index i = 0; i < n && xyz->next(v) != 0; ++i) {
    if (!finite(0) || (normals >= 0 && !finite(normals))) {
      if (options.drop_non_finite) continue;
      throw non_finite_point(file, {xyz->line(), std::nullopt}, next + static_cast<std::uint64_t>(i),
                             "a non-finite coordinate or normal (NaN or Inf)");
    }
    block.positions.row(kept) << v[0], v[1], v[2];
    if (normals >= 0) block.normals.row(kept) << v[normals], v[normals + 1], v[normals + 2];
    if (rgb >= 0)
      for (int k = 0; k < 3; ++k) block.colors(kept, k) = io::text_color_byte(v[static_cast<std::size_t>(rgb + k)]);
    ++kept;
  }
  block.positions.conservativeResize(kept, 3);
  if (normals >= 0) block.normals.conservativeResize(kept, 3);
  if (rgb >= 0) block.colors.conservativeResize(kept, 3);
  release_read(xyz->offset());
}

void PointStream::Impl::read_ptx(Eigen::Index n, PointCloud& block) {
  block.positions.resize(n, 3);
  if (colors) block.colors.resize(n, 3);
  io::PtxPoint p;
  Eigen::Index kept = 0;
  for (Eigen::Index i = 0; i < n && ptx->next(p); ++i) {
    if (!p.position.allFinite()) {
      if (options.drop_non_finite) continue;
      throw non_finite_point(file, {ptx->line(), std::nullopt}, next + static_cast<std::uint64_t>(i),
                             "a non-finite coordinate (NaN or Inf)");
    }
    if (colors)
      for (int k = 0; k < 3; ++k) block.colors(kept, k) = p.rgb[static_cast<std::size_t>(k)];
    block.positions.row(kept++) = p.position.transpose();
  }
  block.positions.conservativeResize(kept, 3);
  if (colors) block.colors.conservativeResize(kept, 3);
  release_read(ptx->offset());
}

void PointStream::Impl::read_las(Eigen::Index n, PointCloud& block) {
  const std::string_view bytes = mapped->view();
  block.positions.resize(n, 3);
  if (colors) block.colors.resize(n, 3);
  Eigen::Index kept = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::uint64_t record = next + static_cast<std::uint64_t>(i);
    const Eigen::Vector3d x = las->position(bytes, record);
    if (x.allFinite()) {
      if (colors) {
        const std::array<std::uint16_t, 3> c = las->color(bytes, record);
        for (int k = 0; k < 3; ++k)
          block.colors(kept, k) = io::wide_color_byte(c[static_cast<std::size_t>(k)], eight_bit);
      }
      block.positions.row(kept++) = x.transpose();
    } else if (!options.drop_non_finite)
      throw InputError(
          file, FileLocation{std::nullopt, las->first + record * las->record},
          "point " + std::to_string(record) + ": its coordinates overflow (integer times the header's scale)");
  }
  block.positions.conservativeResize(kept, 3);
  if (colors) block.colors.conservativeResize(kept, 3);
  const std::size_t begin = las->first + static_cast<std::size_t>(next) * las->record;
  mapped->release(begin, begin + static_cast<std::size_t>(n) * las->record);
}

void PointStream::Impl::read_e57(Eigen::Index n, PointCloud& block) {
  e57->read(static_cast<std::uint64_t>(n), block.positions, located, colors ? &block.colors : nullptr);
  Eigen::Index kept = 0;
  for (Eigen::Index i = 0; i < block.positions.rows(); ++i) {
    if (block.positions.row(i).allFinite()) {
      if (colors) block.colors.row(kept) = block.colors.row(i);
      block.positions.row(kept++) = block.positions.row(i);
    } else if (!options.drop_non_finite) {
      const auto& at = located[static_cast<std::size_t>(i)];
      throw non_finite_point(file, {std::nullopt, at}, points + static_cast<std::uint64_t>(i),
                             at ? "a non-finite coordinate (NaN or Inf)" : "a coordinate that overflows when posed");
    }
  }
  points += static_cast<std::uint64_t>(block.positions.rows());
  block.positions.conservativeResize(kept, 3);
  if (colors) block.colors.conservativeResize(kept, 3);
  for (const auto& [begin, end] : e57->finished_bytes()) mapped->release(begin, end);
}

void PointStream::Impl::open_pcd() {
  pcd_layout = io::pcd::read_layout(file, mapped->view());
  std::size_t given_back = 0;  // the checking pass's pages go back as it reads
  pcd.emplace(file, mapped->view(), *pcd_layout, [&](std::size_t offset) {
    mapped->release(given_back, offset);
    given_back = offset;
  });
}

void PointStream::Impl::read_pcd(Eigen::Index n, PointCloud& block) {
  const io::pcd::Roles& roles = pcd_layout->roles;
  const bool normals = roles.normals();
  block.positions.resize(n, 3);
  if (normals) block.normals.resize(n, 3);
  if (colors) block.colors.resize(n, 3);
  Eigen::Index kept = 0;
  for (Eigen::Index i = 0; i < n && pcd->next(); ++i) {
    Eigen::Vector3d p, q = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) p(k) = pcd->value(roles.position[k]);
    if (p.array().isNaN().any()) continue;  // no point
    if (normals)
      for (int k = 0; k < 3; ++k) q(k) = pcd->value(roles.normal[k]);
    if (!p.allFinite() || !q.allFinite()) {
      if (options.drop_non_finite) continue;
      throw non_finite_point(file, pcd->location(), next + static_cast<std::uint64_t>(i),
                             "an infinite coordinate or a non-finite normal");
    }
    block.positions.row(kept) = p.transpose();
    if (normals) block.normals.row(kept) = q.transpose();
    if (colors && roles.packed_rgb >= 0) {
      const auto rgb = io::pcd::packed_color(pcd->value(roles.packed_rgb),
                                             pcd_layout->fields[static_cast<std::size_t>(roles.packed_rgb)]);
      for (int k = 0; k < 3; ++k) block.colors(kept, k) = rgb[static_cast<std::size_t>(k)];
    } else if (colors) {
      for (int k = 0; k < 3; ++k)
        block.colors(kept, k) = io::wide_color_byte(io::pcd::wide_channel(pcd->value(roles.rgb[k])), eight_bit);
    }
    ++kept;
  }
  block.positions.conservativeResize(kept, 3);
  if (normals) block.normals.conservativeResize(kept, 3);
  if (colors) block.colors.conservativeResize(kept, 3);
  if (pcd_layout->data == io::pcd::Data::BinaryCompressed) {
    for (const auto& [begin, end] : pcd->take_read_spans()) mapped->release(begin, end);
  } else {
    release_read(pcd->offset());
  }
}

void PointStream::Impl::read_ply(Eigen::Index n, PointCloud& block) {
  const detail::PlyPoints& p = *ply;
  block.positions.resize(n, 3);
  if (p.layout.normals()) block.normals.resize(n, 3);
  if (colors) block.colors.resize(n, 3);
  const char* base = mapped->data();
  const std::size_t first = p.begin + static_cast<std::size_t>(next) * p.record;
  Eigen::Index kept = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::size_t at = first + static_cast<std::size_t>(i) * p.record;
    const auto value = [&](int k) {
      const auto u = static_cast<std::size_t>(k);
      return io::ply::load_scalar(base + at + p.offsets[u], p.vertex.properties[u].type, p.swap);
    };
    bool finite = true;
    for (int c = 0; c < 3; ++c) {
      block.positions(kept, c) = value(p.layout.pos[static_cast<std::size_t>(c)]);
      finite = finite && std::isfinite(block.positions(kept, c));
      if (p.layout.normals()) {
        block.normals(kept, c) = value(p.layout.nrm[static_cast<std::size_t>(c)]);
        finite = finite && std::isfinite(block.normals(kept, c));
      }
    }
    if (finite && colors)
      for (int c = 0; c < 3; ++c) {
        const int k = p.layout.rgb[static_cast<std::size_t>(c)];
        block.colors(kept, c) = io::ply::to_color(value(k), p.vertex.properties[static_cast<std::size_t>(k)].type);
      }
    if (finite)
      ++kept;
    else if (!options.drop_non_finite)
      throw InputError(file, FileLocation{std::nullopt, at},
                       io::ply::element_what(p.vertex, next + static_cast<std::uint64_t>(i)) +
                           " has a non-finite coordinate or normal");
  }
  block.positions.conservativeResize(kept, 3);
  if (p.layout.normals()) block.normals.conservativeResize(kept, 3);
  if (colors) block.colors.conservativeResize(kept, 3);
  mapped->release(first, first + static_cast<std::size_t>(n) * p.record);
}

}  // namespace clustersurf
