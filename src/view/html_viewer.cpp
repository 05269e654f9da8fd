#include "io/atomic_file.hpp"
#include "view/patch_grid.hpp"
#include "view/viewer_template.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/view/html_viewer.hpp>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <numeric>
#include <string>
#include <type_traits>
#include <vector>

namespace clustersurf {

namespace {

/// A binary block of the page: little-endian bytes and how the viewer types them.
struct Blob {
  std::string name;
  std::string type;  // f32 | f64 | i32 | u32 | u8
  std::size_t length = 0;
  std::vector<unsigned char> bytes;
};

template <class T>
constexpr const char* type_name() {
  if constexpr (std::is_same_v<T, float>)
    return "f32";
  else if constexpr (std::is_same_v<T, double>)
    return "f64";
  else if constexpr (std::is_same_v<T, std::int32_t>)
    return "i32";
  else if constexpr (std::is_same_v<T, std::uint32_t>)
    return "u32";
  else {
    static_assert(std::is_same_v<T, std::uint8_t>);
    return "u8";
  }
}

template <class T>
Blob make_blob(std::string name, const std::vector<T>& values) {
  Blob b{std::move(name), type_name<T>(), values.size(), std::vector<unsigned char>(values.size() * sizeof(T))};
  if (!values.empty()) std::memcpy(b.bytes.data(), values.data(), b.bytes.size());
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1)
    for (std::size_t i = 0; i < b.bytes.size(); i += sizeof(T))
      std::reverse(b.bytes.begin() + i, b.bytes.begin() + i + sizeof(T));
  return b;
}

/// Writes `bytes` as base64 (RFC 4648, padded) in chunks.
void write_base64(io::AtomicFile& out, const std::vector<unsigned char>& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  constexpr std::size_t kChunk = 3 * 65536;
  std::string text;
  text.reserve(kChunk / 3 * 4);
  for (std::size_t start = 0; start < bytes.size(); start += kChunk) {
    const std::size_t stop = std::min(bytes.size(), start + kChunk);
    text.clear();
    std::size_t i = start;
    for (; i + 3 <= stop; i += 3) {
      const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (std::uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
      text += kAlphabet[(v >> 18) & 63], text += kAlphabet[(v >> 12) & 63];
      text += kAlphabet[(v >> 6) & 63], text += kAlphabet[v & 63];
    }
    if (i < stop) {  // only in the last chunk (kChunk is a multiple of 3)
      const bool two = i + 1 < stop;
      const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (two ? std::uint32_t{bytes[i + 1]} << 8 : 0u);
      text += kAlphabet[(v >> 18) & 63], text += kAlphabet[(v >> 12) & 63];
      text += two ? kAlphabet[(v >> 6) & 63] : '=';
      text += '=';
    }
    out.write(text);
  }
}

/// Indices of the embedded points, in the order they are stored. The kept points are all, or
/// floor(k·n / max) for k < max; they are stored in the order j·stride mod m (stride ≈ 0.618 m,
/// coprime with m), so every prefix is spread evenly over the input.
std::vector<std::size_t> embedded_points(std::size_t n, std::size_t max_points) {
  const std::size_t m = max_points == 0 ? n : std::min(n, max_points);
  std::size_t stride = std::max<std::size_t>(1, static_cast<std::size_t>(0.6180339887498949 * static_cast<double>(m)));
  while (std::gcd(stride, m) != 1) ++stride;
  std::vector<std::size_t> keep(m);
  std::size_t k = 0;
  for (std::size_t j = 0; j < m; ++j, k = (k + stride) % m)
    keep[j] = k * (n / m) + k * (n % m) / m;  // floor(k·n / m) without overflow for m < 2³²
  return keep;
}

/// What the page will show of a glTF binary file: its vertex and triangle counts.
struct GlbSummary {
  std::size_t vertices = 0, triangles = 0;
};

/// Checks that `glb` is a self-contained glTF 2.0 binary the page can parse, and counts it.
GlbSummary check_glb(const GlbMesh& glb) {
  const std::vector<std::uint8_t>& b = glb.bytes;
  const auto fail = [&](std::uint64_t at, const std::string& why) {
    return InputError(glb.file, FileLocation{std::nullopt, at}, why);
  };
  const auto u32 = [&](std::size_t at) {
    return std::uint32_t{b[at]} | std::uint32_t{b[at + 1]} << 8 | std::uint32_t{b[at + 2]} << 16 |
           std::uint32_t{b[at + 3]} << 24;
  };
  if (b.size() < 20 || u32(0) != 0x46546C67) throw fail(0, "not a glTF binary (.glb) file: no \"glTF\" header");
  if (u32(4) != 2) throw fail(4, "glTF version " + std::to_string(u32(4)) + ", the viewer reads version 2");
  if (u32(8) != b.size())
    throw fail(8, "the header gives " + std::to_string(u32(8)) + " bytes, the file has " + std::to_string(b.size()));
  const std::uint32_t json_length = u32(12);
  if (u32(16) != 0x4E4F534A) throw fail(16, "the first chunk is not the JSON chunk");
  if (json_length > b.size() - 20) throw fail(12, "the JSON chunk runs past the end of the file");
  GlbSummary summary;
  try {
    const auto json = nlohmann::json::parse(b.begin() + 20, b.begin() + 20 + json_length);
    for (const char* list : {"buffers", "images"})
      for (const auto& item : json.value(list, nlohmann::json::array()))
        if (item.contains("uri") && !item.at("uri").get<std::string>().starts_with("data:"))
          throw fail(20, std::string("it refers to an external file (") + list + " uri \"" +
                             item.at("uri").get<std::string>() + "\"): only self-contained .glb files can be embedded");
    const auto& accessors = json.value("accessors", nlohmann::json::array());
    const auto count = [&](const nlohmann::json& index) {
      return accessors.at(index.get<std::size_t>()).at("count").get<std::size_t>();
    };
    for (const auto& m : json.value("meshes", nlohmann::json::array()))
      for (const auto& primitive : m.at("primitives")) {
        const auto& attributes = primitive.at("attributes");
        const std::size_t vertices = attributes.contains("POSITION") ? count(attributes.at("POSITION")) : 0;
        summary.vertices += vertices;
        if (primitive.value("mode", 4) == 4)
          summary.triangles += (primitive.contains("indices") ? count(primitive.at("indices")) : vertices) / 3;
      }
  } catch (const nlohmann::json::exception& e) {
    throw fail(20, std::string("malformed glTF JSON chunk: ") + e.what());
  }
  return summary;
}

/// The embedded points (float32 positions relative to `center`) and the leaf of each; returns
/// how many are embedded.
std::size_t add_point_blobs(std::vector<Blob>& blobs, const ClusterTree& tree, const PointCloud* cloud,
                            const Eigen::Vector3d& center, std::size_t max_points) {
  std::vector<float> positions;
  std::vector<std::int32_t> leaves;
  if (cloud != nullptr) {
    const std::vector<std::size_t> keep = embedded_points(static_cast<std::size_t>(cloud->size()), max_points);
    positions.resize(3 * keep.size());
    leaves.resize(keep.size());
    for (std::size_t k = 0; k < keep.size(); ++k) {
      for (int c = 0; c < 3; ++c)
        positions[3 * k + static_cast<std::size_t>(c)] =
            static_cast<float>(cloud->positions(static_cast<Eigen::Index>(keep[k]), c) - center[c]);
      leaves[k] = tree.point_leaf[keep[k]];
    }
  }
  blobs.push_back(make_blob("positions", positions));
  blobs.push_back(make_blob("point_leaf", leaves));
  return positions.size() / 3;
}

/// The node table: links, depth, counts, proxy kind, errors and support; returns the leaf count.
std::size_t add_node_blobs(std::vector<Blob>& blobs, const ClusterTree& tree, const Eigen::Vector3d& center) {
  const std::size_t n = tree.nodes.size();
  std::vector<std::int32_t> ints(5 * n);
  std::vector<std::uint8_t> kinds(n);
  std::vector<double> floats(6 * n);
  std::size_t leaf_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const ClusterNode& node = tree.nodes[i];
    ints[5 * i] = node.parent, ints[5 * i + 1] = node.left, ints[5 * i + 2] = node.right;
    ints[5 * i + 3] = static_cast<std::int32_t>(node.depth),
                 ints[5 * i + 4] = static_cast<std::int32_t>(node.point_count);
    kinds[i] = static_cast<std::uint8_t>(node.proxy.kind());
    const Eigen::Vector3d c = node.support.center - center;
    const double values[6] = {node.rms_error, node.max_error, c.x(), c.y(), c.z(), node.support.radius};
    std::copy(std::begin(values), std::end(values), floats.begin() + static_cast<std::ptrdiff_t>(6 * i));
    leaf_count += node.is_leaf() ? 1 : 0;
  }
  blobs.push_back(make_blob("node_int", ints));
  blobs.push_back(make_blob("node_kind", kinds));
  blobs.push_back(make_blob("node_float", floats));
  return leaf_count;
}

/// The proxy patches (patch_grid()) as the page's two blobs.
void add_patch_blobs(std::vector<Blob>& blobs, const ClusterTree& tree, const PointCloud* cloud,
                     const Eigen::Vector3d& center, std::size_t g) {
  detail::PatchGrid grid = detail::patch_grid(tree, cloud, center, g);
  blobs.push_back(make_blob("patch_frame", grid.frames));
  blobs.push_back(make_blob("patch_height", grid.heights));
}

/// The mesh: arrays relative to the center (a TriangleMesh, moved from its origin to the tree's),
/// or a .glb file's bytes as they are (the page places its scene by the tree's origin). Returns
/// the page's mesh record (null without a mesh) and sets `triangles_out`.
nlohmann::json add_mesh_blobs(std::vector<Blob>& blobs, const ClusterTree& tree, const TriangleMesh* mesh,
                              const GlbMesh* glb, const GlbSummary& glb_summary, const Eigen::Vector3d& center,
                              std::size_t& triangles_out) {
  nlohmann::json mesh_info = nullptr;
  if (mesh != nullptr) {
    const Eigen::Vector3d offset = mesh->origin - tree.origin - center;  // -center when the origins agree
    std::vector<float> vertices(3 * static_cast<std::size_t>(mesh->vertices.rows()));
    for (Eigen::Index v = 0; v < mesh->vertices.rows(); ++v)
      for (int c = 0; c < 3; ++c)
        vertices[3 * static_cast<std::size_t>(v) + static_cast<std::size_t>(c)] =
            static_cast<float>(mesh->vertices(v, c) + offset[c]);
    std::vector<std::uint32_t> triangles(3 * static_cast<std::size_t>(mesh->triangles.rows()));
    for (Eigen::Index t = 0; t < mesh->triangles.rows(); ++t)
      for (int c = 0; c < 3; ++c)
        triangles[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(c)] =
            static_cast<std::uint32_t>(mesh->triangles(t, c));
    blobs.push_back(make_blob("mesh_vertices", vertices));
    blobs.push_back(make_blob("mesh_triangles", triangles));
    if (mesh->colors.rows() == mesh->vertices.rows() && mesh->vertices.rows() > 0)  // a scan's colors, or the leaves'
      blobs.push_back(make_blob(
          "mesh_colors", std::vector<std::uint8_t>(mesh->colors.data(), mesh->colors.data() + mesh->colors.size())));
    mesh_info = {{"format", "arrays"}, {"vertices", mesh->vertices.rows()}, {"triangles", mesh->triangles.rows()}};
    triangles_out = static_cast<std::size_t>(mesh->triangles.rows());
  } else if (glb != nullptr) {
    blobs.push_back(make_blob("mesh_glb", glb->bytes));
    mesh_info = {{"format", "glb"}, {"vertices", glb_summary.vertices}, {"triangles", glb_summary.triangles}};
    triangles_out = glb_summary.triangles;
  }
  return mesh_info;
}

/// The page: the template up to its data marker, the metadata and the blobs, the rest.
void write_html(const std::filesystem::path& file, std::string_view page, std::size_t marker,
                const std::string& meta_text, const std::vector<Blob>& blobs) {
  io::AtomicFile out(file);
  out.write(page.substr(0, marker));
  out.write("<script type=\"application/json\" id=\"cs-meta\">");
  out.write(meta_text);
  out.write("</script>\n");
  for (const Blob& b : blobs) {
    out.write("<script type=\"application/octet-stream\" id=\"cs-blob-" + b.name + "\">");
    write_base64(out, b.bytes);
    out.write("</script>\n");
  }
  out.write(page.substr(marker + view::kDataMarker.size()));
  out.commit();
}

ViewerStats write_page(const std::filesystem::path& file, const ClusterTree& tree, const PointCloud* cloud,
                       const TriangleMesh* mesh, const GlbMesh* glb, const ViewerOptions& options) {
  if (options.patch_grid < 2) throw OptionError("the proxy patch grid needs at least 2 vertices per side");
  if (tree.nodes.empty()) throw OptionError("the tree has no nodes");
  const GlbSummary glb_summary = glb != nullptr ? check_glb(*glb) : GlbSummary{};
  if (cloud != nullptr) {
    require_tree_input(tree, cloud->positions);
    if (tree.point_leaf.size() != static_cast<std::size_t>(cloud->size()))
      throw OptionError(
          "the tree holds no point-to-leaf table (it was built without BuildOptions::keep_point_leaves): rebuild it "
          "with them");
  }
  const std::string_view page = view::viewer_template();
  const std::size_t marker = page.find(view::kDataMarker);
  if (marker == std::string_view::npos) throw IoError("internal error: the viewer template has no data marker");

  const Eigen::Vector3d center =
      tree.bbox.empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(0.5 * (tree.bbox.min + tree.bbox.max));
  const std::size_t n = tree.nodes.size();
  const std::size_t g = options.patch_grid;
  std::vector<Blob> blobs;
  ViewerStats stats;
  stats.nodes = n;
  stats.points = add_point_blobs(blobs, tree, cloud, center, options.max_points);
  const std::size_t leaf_count = add_node_blobs(blobs, tree, center);
  add_patch_blobs(blobs, tree, cloud, center, g);
  const nlohmann::json mesh_info = add_mesh_blobs(blobs, tree, mesh, glb, glb_summary, center, stats.triangles);

  nlohmann::json blob_info = nlohmann::json::object();
  for (const Blob& b : blobs) blob_info[b.name] = {{"type", b.type}, {"length", b.length}};
  const nlohmann::json meta = {{"version", 1},
                               {"title", options.title},
                               {"origin", {tree.origin.x(), tree.origin.y(), tree.origin.z()}},
                               {"center", {center.x(), center.y(), center.z()}},
                               {"up", tree.up == UpAxis::Z ? "z" : "y"},
                               {"diagonal", tree.bbox.diagonal()},
                               {"nodes", n},
                               {"leaves", leaf_count},
                               {"points", stats.points},
                               {"input_points", tree.input_points},
                               {"patch_grid", g},
                               {"error_threshold", tree.error_threshold},
                               {"mesh", mesh_info},
                               {"blobs", blob_info}};
  std::string meta_text = meta.dump(-1, ' ', true);  // ASCII: "</script>" can only come from '<'
  for (std::size_t at = 0; (at = meta_text.find('<', at)) != std::string::npos;) meta_text.replace(at, 1, "\\u003c");

  write_html(file, page, marker, meta_text, blobs);
  std::error_code ec;
  stats.bytes = std::filesystem::file_size(file, ec);
  return stats;
}

}  // namespace

GlbMesh read_glb_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw IoError(file.string() + ": cannot open: " + std::strerror(errno));
  GlbMesh glb{std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()), file};
  if (in.bad()) throw IoError(file.string() + ": read error");
  return glb;
}

ViewerStats write_viewer_html(const std::filesystem::path& file, const ClusterTree& tree, const PointCloud* cloud,
                              const TriangleMesh* mesh, const ViewerOptions& options) {
  return write_page(file, tree, cloud, mesh, nullptr, options);
}

ViewerStats write_viewer_html(const std::filesystem::path& file, const ClusterTree& tree, const PointCloud* cloud,
                              const GlbMesh& mesh, const ViewerOptions& options) {
  return write_page(file, tree, cloud, nullptr, &mesh, options);
}

}  // namespace clustersurf
