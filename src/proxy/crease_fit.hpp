#pragma once
// A leaf on a sharp edge: two planes meeting along a crease inside the cluster (MPU's edge
// function), for clusters whose points lie on two faces.

#include <clustersurf/proxy/proxy.hpp>

#include <optional>
#include <span>

namespace clustersurf::detail {

/// A crease proxy and its error over the cluster.
struct CreaseFit {
  CreaseProxy proxy;
  ProxyError error;
};

/// The crease that fits points[range] best, or nullopt when they do not lie on two faces
/// meeting inside the cluster. Two planes are fitted by k-planes (each plane the least-squares
/// plane of its group, each point to the nearer plane, until no point changes side), started
/// from the split across each tangent axis of `frame`; the planes are turned to agree on the
/// outside (unfolding the crease takes one normal to the other), and the edge's kind (convex:
/// max, concave: min) is the one of smallest RMS. Refused when a face has fewer than 3 points
/// or does not pin its plane down (its points along a line: as wide as 3 times its residual at
/// least), when the edge passes farther than half the cluster's `extent` from its centroid (nearly
/// parallel planes: a step, not a crease), or when the faces face apart (normals more than 120
/// degrees apart: as likely both sides of a thin part as a wedge).
std::optional<CreaseFit> fit_crease(const Points& points, std::span<const std::uint32_t> range, const Frame& frame,
                                    double extent);

}  // namespace clustersurf::detail
