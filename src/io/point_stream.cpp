// Point files read a block at a time: binary PLY points, LAS, E57, PCD (ascii, binary and
// binary_compressed), PTX and XYZ text in place, anything else whole.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_stream.hpp>

#include "io/mapped_file.hpp"
#include "io/pcd_format.hpp"
#include "io/ply_format.hpp"
#include "io/readers.hpp"

#include <algorithm>
#include <array>
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
  UpAxis up = UpAxis::Y;
};

std::optional<PlyPoints> ply_points(const std::filesystem::path& file, std::string_view bytes) {
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

/// The error for point `index` (0-based), found at `where`, that has `what` (a non-finite value).
InputError non_finite_point(const std::filesystem::path& file, const FileLocation& where, std::uint64_t index,
                            const std::string& what) {
  return InputError(
      file, where,
      "point " + std::to_string(index) + " (0-based) has " + what + "; use the option to drop such points");
}

}  // namespace

struct PointStream::Impl {
  std::filesystem::path file;
  ReadOptions options;
  std::optional<io::MappedFile> mapped;
  std::optional<PlyPoints> ply;
  std::optional<io::LasPoints> las;
  std::optional<io::E57Points> e57;
  std::optional<io::XyzLines> xyz;
  std::optional<io::PtxLines> ptx;
  std::optional<io::pcd::Layout> pcd_layout;
  std::optional<io::pcd::Records> pcd;
  std::uint64_t text_points = 0;  // points of an XYZ or PTX file, counted when opened
  bool xyz_normals = false;
  bool ptx_colored = false;  // PTX: the points have colors
  bool colors = false;       // blocks carry colors
  bool eight_bit = false;    // LAS, PCD red, green, blue: every color is at most 255 (read as it is)
  std::size_t released = 0;  // bytes of a text or PCD file given back to the system
  bool failed = false;       // a read threw: the text parser is past the point it refused
  std::uint64_t points = 0;  // E57: valid points decoded so far (for messages)
  std::vector<std::optional<std::uint64_t>> located;  // E57: where each point of a block was found non-finite
  PointCloud whole;  // the file read whole, in the file's coordinates, when not streamed
  std::uint64_t next = 0;

  std::uint64_t size() const {
    return ply          ? ply->vertex.count
           : las        ? las->count
           : e57        ? e57->records()
           : pcd        ? pcd_layout->points
           : xyz || ptx ? text_points
                        : static_cast<std::uint64_t>(whole.size());
  }
  bool streamed() const { return ply || las || e57 || pcd || xyz || ptx; }
  /// Parses the text file once (its count, an XYZ file's columns, every error the reader
  /// would give), then starts over for the points.
  void open_text();
  /// Back to the text file's first point.
  void restart_text() {
    if (xyz)
      xyz.emplace(file, mapped->view());
    else
      ptx.emplace(file, mapped->view());
  }
  /// The next `n` XYZ points into `block`.
  void read_xyz(Eigen::Index n, PointCloud& block);
  /// Whether blocks carry colors (as read_point_cloud() gives them); for LAS and PCD's red, green
  /// and blue fields, a look at every point's color says whether they are 8-bit (`eight_bit`).
  bool find_colors();
  /// PCD: the largest red, green or blue value (0..65535) of the points that are points.
  std::uint16_t pcd_color_maximum();
  /// The next `n` PTX points into `block` (positions only).
  void read_ptx(Eigen::Index n, PointCloud& block);
  /// Gives back the file's pages read so far (up to byte `offset`).
  void release_read(std::size_t offset) {
    mapped->release(released, offset);
    released = offset;
  }
  /// The next `n` LAS records into `block` (positions only: LAS has no normals).
  void read_las(Eigen::Index n, PointCloud& block);
  /// The next `n` E57 records into `block` (positions only; the invalid ones left out).
  void read_e57(Eigen::Index n, PointCloud& block);
  /// Opens a PCD file (binary_compressed data is decoded through once here, to check it).
  void open_pcd();
  /// The next `n` PCD records into `block` (those whose position is NaN, PCL's "no point", left out).
  void read_pcd(Eigen::Index n, PointCloud& block);
};

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
    std::array<double, 7> v{};
    for (std::size_t columns; (columns = counting.next(v)) != 0; ++text_points) {
      xyz_normals = columns == 6;
      release(counting.offset());
    }
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
    eight_bit = las->eight_bit_colors(mapped->view());
    mapped->release(0, mapped->view().size());  // the look at every record's color
    return true;
  }
  return xyz ? false : whole.has_colors();
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
  block.positions.resize(n, 3);
  if (xyz_normals) block.normals.resize(n, 3);
  std::array<double, 7> v{};
  Eigen::Index kept = 0;
  for (Eigen::Index i = 0; i < n && xyz->next(v) != 0; ++i) {
    const bool finite =
        std::all_of(v.begin(), v.begin() + (xyz_normals ? 6 : 3), [](double x) { return std::isfinite(x); });
    if (!finite) {
      if (options.drop_non_finite) continue;
      throw non_finite_point(file, {xyz->line(), std::nullopt}, next + static_cast<std::uint64_t>(i),
                             "a non-finite coordinate or normal (NaN or Inf)");
    }
    block.positions.row(kept) << v[0], v[1], v[2];
    if (xyz_normals) block.normals.row(kept) << v[3], v[4], v[5];
    ++kept;
  }
  block.positions.conservativeResize(kept, 3);
  if (xyz_normals) block.normals.conservativeResize(kept, 3);
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
    impl_->ply = ply_points(file, bytes);
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
         : impl_->xyz ? impl_->xyz_normals
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
  const PlyPoints& p = *s.ply;
  block.positions.resize(n, 3);
  if (p.layout.normals()) block.normals.resize(n, 3);
  if (s.colors) block.colors.resize(n, 3);
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
    if (finite && s.colors)
      for (int c = 0; c < 3; ++c) {
        const int k = p.layout.rgb[static_cast<std::size_t>(c)];
        block.colors(kept, c) = io::ply::to_color(value(k), p.vertex.properties[static_cast<std::size_t>(k)].type);
      }
    if (finite)
      ++kept;
    else if (!s.options.drop_non_finite)
      throw InputError(s.file, FileLocation{std::nullopt, at},
                       io::ply::element_what(p.vertex, s.next + static_cast<std::uint64_t>(i)) +
                           " has a non-finite coordinate or normal");
  }
  block.positions.conservativeResize(kept, 3);
  if (p.layout.normals()) block.normals.conservativeResize(kept, 3);
  if (s.colors) block.colors.conservativeResize(kept, 3);
  s.mapped->release(first, first + static_cast<std::size_t>(n) * p.record);
  s.next += static_cast<std::uint64_t>(n);
  return true;
}

}  // namespace clustersurf
