// The .cstree codec's shared fields: the CRC-32, proxies and spheres.

#include "cluster/tree_codec.hpp"

#include <zlib.h>

#include <algorithm>
#include <variant>

namespace clustersurf::detail {

std::uint32_t crc_of(std::string_view bytes, std::uint32_t crc, const io::MappedFile* mapped) {
  constexpr std::size_t kChunk = std::size_t{16} << 20;
  uLong c = crc;
  for (std::size_t at = 0; at < bytes.size(); at += kChunk) {
    const std::size_t n = std::min(kChunk, bytes.size() - at);
    c = crc32(c, reinterpret_cast<const Bytef*>(bytes.data() + at), static_cast<uInt>(n));
    if (mapped != nullptr) mapped->release(0, at + n);
  }
  return static_cast<std::uint32_t>(c);
}

void put_proxy(Writer& w, const Proxy& proxy) {
  std::visit(
      [&](const auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, PointProxy>) {
          w.put_vec(p.center);
        } else if constexpr (std::is_same_v<T, PlaneProxy>) {
          w.put_vec(p.point), w.put_vec(p.normal);
        } else if constexpr (std::is_same_v<T, PolyProxy>) {
          w.put_vec(p.frame.origin);
          for (int c = 0; c < 3; ++c) w.put_vec(p.frame.axes.col(c));
          for (double x : p.coeffs) w.put(x);
        } else if constexpr (std::is_same_v<T, CreaseProxy>) {
          w.put_vec(p.a.point), w.put_vec(p.a.normal), w.put_vec(p.b.point), w.put_vec(p.b.normal);
          w.put(p.convex ? 1.0 : 0.0);
        } else {
          w.put_vec(p.center), w.put(p.scale);
          for (double x : p.coeffs) w.put(x);
        }
      },
      proxy.variant());
}

namespace {

PlaneProxy get_plane(Reader& r) {
  PlaneProxy p;
  p.point = r.vec("plane point");
  const std::size_t at = r.pos();
  p.normal = r.vec("plane normal");
  if (std::abs(p.normal.norm() - 1) > 1e-6) r.fail_at(at, "plane normal is not a unit vector");
  return p;
}

}  // namespace

Proxy get_proxy(Reader& r, ProxyKind kind) {
  switch (kind) {
    case ProxyKind::Point:
      return PointProxy{r.vec("point proxy center")};
    case ProxyKind::Plane:
      return get_plane(r);
    case ProxyKind::Crease: {
      CreaseProxy p;
      p.a = get_plane(r);
      p.b = get_plane(r);
      const std::size_t at = r.pos();
      const double convex = r.finite("crease side");
      if (convex != 0 && convex != 1) r.fail_at(at, "crease side must be 0 (concave) or 1 (convex)");
      p.convex = convex == 1;
      return p;
    }
    case ProxyKind::Poly: {
      PolyProxy p;
      p.frame.origin = r.vec("polynomial frame origin");
      const std::size_t at = r.pos();
      for (int c = 0; c < 3; ++c) p.frame.axes.col(c) = r.vec("polynomial frame axis");
      if (!(p.frame.axes.transpose() * p.frame.axes).isIdentity(1e-6))
        r.fail_at(at, "polynomial frame axes are not orthonormal");
      for (double& x : p.coeffs) x = r.finite("polynomial coefficient");
      return p;
    }
    case ProxyKind::Quadric: {
      QuadricProxy p;
      p.center = r.vec("quadric center");
      const std::size_t at = r.pos();
      p.scale = r.finite("quadric scale");
      if (!(p.scale > 0)) r.fail_at(at, "quadric scale must be positive");
      for (double& x : p.coeffs) x = r.finite("quadric coefficient");
      return p;
    }
  }
  return {};
}

Sphere get_sphere(Reader& r, const char* what) {
  Sphere s;
  s.center = r.vec(what);
  const std::size_t at = r.pos();
  s.radius = r.finite(what);
  if (s.radius < 0) r.fail_at(at, std::string(what) + " has a negative radius");
  return s;
}

}  // namespace clustersurf::detail
