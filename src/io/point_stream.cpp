// Point files read a block at a time: which reader a file takes, its counting pass, and the
// blocks handed out (point_blocks.cpp reads each format's blocks).

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_stream.hpp>

#include "io/point_stream_impl.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <optional>

namespace clustersurf {

using detail::PlyPoints;

std::optional<PlyPoints> detail::ply_points(const std::filesystem::path& file, std::string_view bytes) {
  if (!bytes.starts_with("ply")) return std::nullopt;
  const io::ply::Header h = io::ply::parse_header(file, bytes);
  if (h.encoding == io::ply::Encoding::Ascii) return std::nullopt;
  io::ply::check_counts(file, h, bytes);
  PlyPoints out;
  out.begin = h.data_offset;
  out.up = h.up;
  const io::ply::Element* vertex = nullptr;
  for (const io::ply::Element& e : h.elements) {
    if (e.name == "face" && e.count > 0) return std::nullopt;  // a mesh: read_point_cloud() decides
    if (vertex != nullptr) continue;
    if (e.has_lists()) return std::nullopt;
    if (e.name == "vertex")
      vertex = &e;
    else
      out.begin += static_cast<std::size_t>(e.min_binary_record() * e.count);
  }
  if (vertex == nullptr) return std::nullopt;
  out.vertex = *vertex;
  out.layout = io::ply::vertex_layout(file, *vertex);
  for (const io::ply::Property& p : vertex->properties)
    out.offsets.push_back(out.record), out.record += io::ply::scalar_size(p.type);
  out.swap = (h.encoding == io::ply::Encoding::BinaryBig) != (std::endian::native == std::endian::big);
  return out;
}

/// The counting pass over a text file gives its pages back this often, so that it holds no
/// more of the file than a block does.
constexpr std::size_t kReleaseBytes = std::size_t{64} << 20;

void PointStream::Impl::open_text() {
  const std::string_view bytes = mapped->view();
  text_points = 0;
  std::size_t counted = 0;  // bytes given back so far: the pass reads the whole file
  const auto release = [&](std::size_t offset) {
    if (offset - counted >= kReleaseBytes) mapped->release(counted, offset), counted = offset;
  };
  if (xyz) {
    io::XyzLines counting(file, bytes);
    std::array<double, io::XyzLines::kMaxColumns> v{};
    for (; counting.next(v) != 0; ++text_points) release(counting.offset());
    xyz_layout = counting.layout();
  } else {
    io::PtxLines counting(file, bytes);
    io::PtxPoint p;
    for (; counting.next(p); ++text_points) release(counting.offset());
    ptx_colored = counting.colored().value_or(false);
  }
  mapped->release(counted, bytes.size());
  restart_text();
}

bool PointStream::Impl::find_colors() {
  if (ply) return ply->layout.colors();
  if (e57) return e57->has_colors();
  if (ptx) return ptx_colored;
  if (pcd) {
    const io::pcd::Roles& r = pcd_layout->roles;
    if (r.packed_rgb >= 0) return true;
    if (r.rgb[0] < 0 || r.rgb[1] < 0 || r.rgb[2] < 0) return false;
    eight_bit = pcd_color_maximum() <= 255;
    return true;
  }
  if (las) {
    if (!las->has_colors()) return false;
    const std::uint16_t top = las->color_maximum(mapped->view());
    mapped->release(0, mapped->view().size());  // the look at every record's color
    eight_bit = top <= 255;
    return top > 0;  // fields left 0 in every record: no colors
  }
  return xyz ? xyz_layout.colors >= 0 : whole.has_colors();
}

PointStream::PointStream(const std::filesystem::path& file, const ReadOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->file = file;
  impl_->options = options;
  impl_->mapped.emplace(file);
  const std::string_view bytes = impl_->mapped->view();
  const FileFormat format =
      bytes.empty() ? FileFormat::Ply : format_from_magic(bytes).value_or(format_from_extension(file));
  if (format == FileFormat::Las)
    impl_->las = io::las_points(file, bytes);
  else if (format == FileFormat::E57)
    impl_->e57.emplace(file, bytes);
  else if (format == FileFormat::Pcd)
    impl_->open_pcd();
  else if (format == FileFormat::Xyz && !bytes.empty())
    impl_->xyz.emplace(file, bytes), impl_->open_text();
  else if (format == FileFormat::Ptx && !bytes.empty())
    impl_->ptx.emplace(file, bytes), impl_->open_text();
  else
    impl_->ply = detail::ply_points(file, bytes);
  if (!impl_->streamed()) {
    impl_->mapped.reset();
    impl_->whole = read_point_cloud(file, options);
    impl_->whole.positions.rowwise() += impl_->whole.origin.transpose();  // exact: the shift was
    impl_->whole.origin.setZero();
    impl_->whole.attributes.clear();
  }
  impl_->colors = impl_->find_colors();
}

PointStream::~PointStream() = default;

std::uint64_t PointStream::size() const noexcept { return impl_->size(); }
bool PointStream::has_normals() const noexcept {
  return impl_->ply   ? impl_->ply->layout.normals()
         : impl_->pcd ? impl_->pcd_layout->roles.normals()
         : impl_->xyz ? impl_->xyz_layout.normals >= 0
                      : impl_->whole.has_normals();
}
bool PointStream::has_colors() const noexcept { return impl_->colors; }
UpAxis PointStream::up() const noexcept {
  if (impl_->las || impl_->e57 || impl_->ptx) return UpAxis::Z;
  return impl_->ply ? impl_->ply->up : impl_->whole.up;
}
bool PointStream::streamed() const noexcept { return impl_->streamed(); }
void PointStream::rewind() {
  impl_->next = 0;
  impl_->failed = false;
  impl_->points = 0;
  impl_->released = 0;
  if (impl_->xyz || impl_->ptx) impl_->restart_text();
  if (impl_->e57) impl_->e57->rewind();
  if (impl_->pcd) impl_->pcd->rewind();
}

bool PointStream::read(std::size_t count, PointCloud& block) {
  Impl& s = *impl_;
  const std::uint64_t total = s.size();
  if (s.next >= total || count == 0) return false;
  const auto n = static_cast<Eigen::Index>(std::min<std::uint64_t>(count, total - s.next));
  block = PointCloud{};
  if (s.failed)
    throw InputError(s.file, {}, "the points after a refused one are not read: rewind to read the file again");
  if (s.las || s.e57 || s.pcd || s.xyz || s.ptx) {
    try {
      if (s.las)
        s.read_las(n, block);
      else if (s.e57)
        s.read_e57(n, block);
      else if (s.pcd)
        s.read_pcd(n, block);
      else if (s.xyz)
        s.read_xyz(n, block);
      else
        s.read_ptx(n, block);
    } catch (const InputError&) {
      s.failed = true;  // the parser or decoder is past what it refused
      throw;
    }
    s.next += static_cast<std::uint64_t>(n);
    return true;
  }
  if (!s.ply) {
    block.positions = s.whole.positions.middleRows(static_cast<Eigen::Index>(s.next), n);
    if (s.whole.has_normals()) block.normals = s.whole.normals.middleRows(static_cast<Eigen::Index>(s.next), n);
    if (s.whole.has_colors()) block.colors = s.whole.colors.middleRows(static_cast<Eigen::Index>(s.next), n);
    s.next += static_cast<std::uint64_t>(n);
    return true;
  }
  s.read_ply(n, block);
  s.next += static_cast<std::uint64_t>(n);
  return true;
}

}  // namespace clustersurf
