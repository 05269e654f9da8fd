// The noise estimate's local fit (see local_fit.hpp).

#include "cluster/local_fit.hpp"

#include <clustersurf/proxy/proxy.hpp>

#include <cmath>
#include <limits>
#include <vector>

namespace clustersurf::detail {

LocalFit fit_residual(const Points& points, std::span<const std::uint32_t> idx, bool differences) {
  const Frame frame = pca_frame(points, idx);
  const PolyProxy poly = fit_poly_in_frame(frame, points, idx);
  thread_local std::vector<Eigen::Vector3d> local;  // tangent-plane position, residual
  local.clear();
  double ss = 0, s4 = 0;
  for (auto j : idx) {
    const Eigen::Vector3d l = frame.to_local(points.row(j).transpose());
    const double r = l.z() - poly.height(l.x(), l.y());
    local.emplace_back(l.x(), l.y(), r);
    ss += r * r;
    s4 += r * r * r * r;
  }
  double sd = 0;
  for (std::size_t i = 0; differences && i < local.size(); ++i) {
    double nearest = std::numeric_limits<double>::infinity(), dr = 0;
    for (std::size_t j = 0; j < local.size(); ++j) {
      if (j == i) continue;
      const double d = (local[i].head<2>() - local[j].head<2>()).squaredNorm();
      if (d < nearest) nearest = d, dr = local[i].z() - local[j].z();
    }
    sd += dr * dr;
  }
  // Both corrected for the fit's six degrees of freedom: its residuals, and so their
  // differences, carry (k − 6) / k of the noise's variance.
  const auto dof = static_cast<double>(idx.size() - 6);
  const double kurtosis = ss > 0 ? s4 * static_cast<double>(idx.size()) / (ss * ss) : 3;
  return {std::sqrt(ss / dof), std::sqrt(sd / (2 * dof)), kurtosis};
}

}  // namespace clustersurf::detail
