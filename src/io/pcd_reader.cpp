// PCD (the Point Cloud Library's format, versions 0.5-0.7): a text header (FIELDS, SIZE, TYPE,
// COUNT, WIDTH, HEIGHT, VIEWPOINT, POINTS, DATA), then the points as ascii lines (separated by
// spaces, tabs or commas), packed binary records, or binary_compressed (LZF, fields stored one
// after another). Fields: x y z (any case), normal_x/y/z, rgb/rgba (packed) or red/green/blue,
// intensity and classification (kept as attributes); others are skipped. A point whose
// position is NaN is PCL's "no point" and is skipped. The viewpoint is the scanner when it is
// not the default one or the cloud is organized (HEIGHT > 1).

#include "io/pcd_format.hpp"
#include "io/readers.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace clustersurf::io {

namespace {

using pcd::Field;
using pcd::Roles;

/// `x` as a float, NaN kept and magnitudes beyond float's range clamped to it (a plain cast
/// of such a double is undefined).
float to_float(double x) {
  constexpr double kMax = std::numeric_limits<float>::max();
  return std::isnan(x) ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(std::clamp(x, -kMax, kMax));
}

/// Collects the points; `value(f)` gives the first element of field f of the current point.
class PointSink {
 public:
  PointSink(const std::vector<Field>& fields, const Roles& roles, std::size_t expected)
      : fields_(fields), roles_(roles) {
    has_normals_ = roles.normals();
    has_rgb_ = roles.packed_rgb >= 0 || std::all_of(roles.rgb, roles.rgb + 3, [](int f) { return f >= 0; });
    pos_.reserve(3 * expected);
  }

  /// Adds the current point unless its position is NaN (PCL's "no point").
  template <class Value>
  void add(Value&& value) {
    double p[3];
    for (int k = 0; k < 3; ++k) p[k] = value(roles_.position[k]);
    if (std::isnan(p[0]) || std::isnan(p[1]) || std::isnan(p[2])) return;
    pos_.insert(pos_.end(), p, p + 3);
    if (has_normals_)
      for (int k = 0; k < 3; ++k) nrm_.push_back(value(roles_.normal[k]));
    if (has_rgb_) {
      if (roles_.packed_rgb >= 0) {
        const auto rgb =
            pcd::packed_color(value(roles_.packed_rgb), fields_[static_cast<std::size_t>(roles_.packed_rgb)]);
        wide_rgb_.insert(wide_rgb_.end(), rgb.begin(), rgb.end());
      } else {
        for (int k = 0; k < 3; ++k) wide_rgb_.push_back(pcd::wide_channel(value(roles_.rgb[k])));
      }
    }
    if (roles_.intensity >= 0) intensity_.push_back(to_float(value(roles_.intensity)));
    if (roles_.classification >= 0) classification_.push_back(to_float(value(roles_.classification)));
  }

  void finish(PointCloud& cloud) {
    const auto n = static_cast<Eigen::Index>(pos_.size() / 3);
    cloud.positions = Eigen::Map<Points>(pos_.data(), n, 3);
    if (has_normals_) cloud.normals = Eigen::Map<Points>(nrm_.data(), n, 3);
    if (has_rgb_ && n > 0) {
      // 16-bit red/green/blue fields (PDAL writes them) are scaled unless they hold 8-bit values.
      const bool eight_bit = *std::max_element(wide_rgb_.begin(), wide_rgb_.end()) <= 255;
      cloud.colors.resize(n, 3);
      for (Eigen::Index i = 0; i < 3 * n; ++i)
        cloud.colors.data()[i] = wide_color_byte(wide_rgb_[static_cast<std::size_t>(i)], eight_bit);
    }
    if (roles_.intensity >= 0)
      cloud.attributes.push_back({"intensity", Eigen::Map<Eigen::VectorXf>(intensity_.data(), n)});
    if (roles_.classification >= 0)
      cloud.attributes.push_back({"classification", Eigen::Map<Eigen::VectorXf>(classification_.data(), n)});
  }

 private:
  const std::vector<Field>& fields_;
  const Roles& roles_;
  bool has_normals_ = false, has_rgb_ = false;
  std::vector<double> pos_, nrm_;
  std::vector<std::uint16_t> wide_rgb_;
  std::vector<float> intensity_, classification_;
};

}  // namespace

ParsedFile read_pcd(const std::filesystem::path& file, std::string_view bytes) {
  const pcd::Layout layout = pcd::read_layout(file, bytes);
  ParsedFile out;
  PointSink sink(layout.fields, layout.roles, static_cast<std::size_t>(layout.points));
  if (layout.data != pcd::Data::BinaryCompressed) {
    pcd::Records records(file, bytes, layout);
    while (records.next()) sink.add([&](int f) { return records.value(f); });
  } else {
    // The fields one after another, decompressed whole in one pass (pcd::Records decodes the
    // data twice, to stream it: once to check it, then a field at a time).
    const pcd::CompressedData data = pcd::compressed_data(file, bytes, layout);
    std::vector<char> unpacked(static_cast<std::size_t>(data.unpacked));
    LzfStream decoder(file, data.packed, data.begin);
    decoder.read(unpacked.data(), data.unpacked);
    decoder.require_finished();
    const std::uint64_t n = layout.points;
    for (std::uint64_t i = 0; i < n; ++i)
      sink.add([&](int fi) {
        const Field& f = layout.fields[static_cast<std::size_t>(fi)];
        return pcd::decode(unpacked.data() + f.offset * n + i * f.size * f.count, f.type, f.size);
      });
  }
  sink.finish(out.cloud);
  // Infinite coordinates are errors (NaN is PCL's "no point" and was skipped); the dispatcher
  // names them by point.
  if (!out.cloud.positions.allFinite() || (out.cloud.has_normals() && !out.cloud.normals.allFinite()))
    out.first_non_finite = FileLocation{layout.data_line, std::nullopt};
  const double* viewpoint = layout.viewpoint;
  const bool default_viewpoint = viewpoint[0] == 0 && viewpoint[1] == 0 && viewpoint[2] == 0;
  if ((!default_viewpoint || layout.height > 1) && out.cloud.size() > 0) {
    out.cloud.scanner_positions = Points(1, 3);
    out.cloud.scanner_positions << viewpoint[0], viewpoint[1], viewpoint[2];
    out.cloud.scanner_of_point.assign(static_cast<std::size_t>(out.cloud.size()), 0);
  }
  return out;
}

}  // namespace clustersurf::io
