// Point files read a block at a time: binary PLY points in place, anything else whole.

#include <clustersurf/errors.hpp>
#include <clustersurf/point_stream.hpp>

#include "io/mapped_file.hpp"
#include "io/ply_format.hpp"

#include <cmath>
#include <optional>

namespace clustersurf {

namespace {

/// The vertex element of a binary PLY file of points, and where its records start; nullopt
/// when the file is not one (ascii, faces, lists in the vertex element or before it).
struct PlyPoints {
  io::ply::Element vertex;
  io::ply::VertexLayout layout;
  std::vector<std::size_t> offsets;  // of each property inside a record
  std::size_t record = 0;
  std::size_t begin = 0;  // byte offset of the first record
  bool swap = false;
};

std::optional<PlyPoints> ply_points(const std::filesystem::path& file, std::string_view bytes) {
  if (!bytes.starts_with("ply")) return std::nullopt;
  const io::ply::Header h = io::ply::parse_header(file, bytes);
  if (h.encoding == io::ply::Encoding::Ascii) return std::nullopt;
  io::ply::check_counts(file, h, bytes);
  PlyPoints out;
  out.begin = h.data_offset;
  const io::ply::Element* vertex = nullptr;
  for (const io::ply::Element& e : h.elements) {
    if (e.name == "face" && e.count > 0) return std::nullopt;  // a mesh: read_point_cloud() decides
    if (vertex != nullptr) continue;
    if (e.has_lists()) return std::nullopt;
    if (e.name == "vertex") vertex = &e;
    else out.begin += static_cast<std::size_t>(e.min_binary_record() * e.count);
  }
  if (vertex == nullptr) return std::nullopt;
  out.vertex = *vertex;
  out.layout = io::ply::vertex_layout(file, *vertex);
  for (const io::ply::Property& p : vertex->properties) out.offsets.push_back(out.record), out.record += io::ply::scalar_size(p.type);
  out.swap = (h.encoding == io::ply::Encoding::BinaryBig) != (std::endian::native == std::endian::big);
  return out;
}

}  // namespace

struct PointStream::Impl {
  std::filesystem::path file;
  ReadOptions options;
  std::optional<io::MappedFile> mapped;
  std::optional<PlyPoints> ply;
  PointCloud whole;  // the file read whole, in the file's coordinates, when not streamed
  std::uint64_t next = 0;

  std::uint64_t size() const { return ply ? ply->vertex.count : static_cast<std::uint64_t>(whole.size()); }
};

PointStream::PointStream(const std::filesystem::path& file, const ReadOptions& options) : impl_(std::make_unique<Impl>()) {
  impl_->file = file;
  impl_->options = options;
  impl_->mapped.emplace(file);
  impl_->ply = ply_points(file, impl_->mapped->view());
  if (!impl_->ply) {
    impl_->mapped.reset();
    impl_->whole = read_point_cloud(file, options);
    impl_->whole.positions.rowwise() += impl_->whole.origin.transpose();  // exact: the shift was
    impl_->whole.origin.setZero();
    impl_->whole.colors.resize(0, 3);
    impl_->whole.attributes.clear();
  }
}

PointStream::~PointStream() = default;

std::uint64_t PointStream::size() const noexcept { return impl_->size(); }
bool PointStream::has_normals() const noexcept { return impl_->ply ? impl_->ply->layout.normals() : impl_->whole.has_normals(); }
bool PointStream::streamed() const noexcept { return impl_->ply.has_value(); }
void PointStream::rewind() { impl_->next = 0; }

bool PointStream::read(std::size_t count, PointCloud& block) {
  Impl& s = *impl_;
  const std::uint64_t total = s.size();
  if (s.next >= total || count == 0) return false;
  const auto n = static_cast<Eigen::Index>(std::min<std::uint64_t>(count, total - s.next));
  block = PointCloud{};
  if (!s.ply) {
    block.positions = s.whole.positions.middleRows(static_cast<Eigen::Index>(s.next), n);
    if (s.whole.has_normals()) block.normals = s.whole.normals.middleRows(static_cast<Eigen::Index>(s.next), n);
    s.next += static_cast<std::uint64_t>(n);
    return true;
  }
  const PlyPoints& p = *s.ply;
  block.positions.resize(n, 3);
  if (p.layout.normals()) block.normals.resize(n, 3);
  const char* base = s.mapped->data();
  const std::size_t first = p.begin + static_cast<std::size_t>(s.next) * p.record;
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
    if (finite) ++kept;
    else if (!s.options.drop_non_finite)
      throw InputError(s.file, FileLocation{std::nullopt, at},
                       io::ply::element_what(p.vertex, s.next + static_cast<std::uint64_t>(i)) + " has a non-finite coordinate or normal");
  }
  block.positions.conservativeResize(kept, 3);
  if (p.layout.normals()) block.normals.conservativeResize(kept, 3);
  s.mapped->release(first, first + static_cast<std::size_t>(n) * p.record);
  s.next += static_cast<std::uint64_t>(n);
  return true;
}

}  // namespace clustersurf
