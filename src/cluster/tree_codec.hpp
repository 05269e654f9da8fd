#pragma once
// The .cstree codec's pieces: a writer that keeps the CRC-32 of what it wrote, a reader whose
// every field is checked and located, and the fields the format shares between records
// (proxies, spheres, enumerations). tree_file.cpp lays out the records.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/errors.hpp>

#include "io/atomic_file.hpp"
#include "io/mapped_file.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <type_traits>

namespace clustersurf::detail {

/// CRC-32 of `bytes` continuing `crc`, in chunks (zlib counts lengths in 32 bits). With a
/// mapped file, the pages already counted are released as it goes.
std::uint32_t crc_of(std::string_view bytes, std::uint32_t crc, const io::MappedFile* mapped = nullptr);

/// Appends a tree file's bytes to a string, or, with a sink, passes them on a few MiB at a
/// time (a large tree is never held twice), keeping the CRC-32 of all bytes so far.
class Writer {
 public:
  explicit Writer(io::AtomicFile* sink = nullptr) : sink_(sink) {}
  template <class T>
  void put(T v) {
    static_assert(std::is_arithmetic_v<T>);
    raw(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void put_vec(const Eigen::Vector3d& v) { put(v.x()), put(v.y()), put(v.z()); }
  void raw(const char* p, std::size_t n) {
    out_.append(p, n);
    if (sink_ != nullptr && out_.size() >= kFlushBytes) flush();
  }
  /// The CRC-32 of every byte written so far.
  std::uint32_t crc() {
    settle();
    return crc_;
  }
  /// Hands the buffered bytes to the sink (with one).
  void flush() {
    settle();
    if (sink_ == nullptr) return;
    sink_->write(out_.data(), out_.size());
    out_.clear();
    counted_ = 0;
  }
  std::string& bytes() { return out_; }

 private:
  static constexpr std::size_t kFlushBytes = std::size_t{4} << 20;
  void settle() {
    crc_ = crc_of(std::string_view(out_).substr(counted_), crc_);
    counted_ = out_.size();
  }
  io::AtomicFile* sink_;
  std::string out_;
  std::size_t counted_ = 0;  // bytes of out_ already in crc_
  std::uint32_t crc_ = 0;
};

/// Reads a tree file's fields, each checked: a short file or a value out of range fails with
/// the byte offset and what was expected (InputError).
class Reader {
 public:
  Reader(std::string_view bytes, const std::filesystem::path& file) : bytes_(bytes), file_(file) {}

  template <class T>
  T get(const char* what) {
    if (sizeof(T) > bytes_.size() - pos_) fail("file is truncated: expected " + std::string(what));
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  double finite(const char* what) {
    const std::size_t at = pos_;
    const double v = get<double>(what);
    if (!std::isfinite(v)) fail_at(at, std::string(what) + " is not a finite number");
    return v;
  }
  Eigen::Vector3d vec(const char* what) {
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k) v(k) = finite(what);
    return v;
  }
  std::size_t pos() const { return pos_; }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  [[noreturn]] void fail(const std::string& msg) const { fail_at(pos_, msg); }
  [[noreturn]] void fail_at(std::size_t at, const std::string& msg) const {
    throw InputError(file_, FileLocation{std::nullopt, at}, msg);
  }

 private:
  std::string_view bytes_;
  const std::filesystem::path& file_;
  std::size_t pos_ = 0;
};

/// Writes a proxy's doubles, in the format's order for its kind.
void put_proxy(Writer& w, const Proxy& proxy);
/// Reads a proxy of `kind`, checked: finite numbers, unit normals, orthonormal frames, a
/// positive quadric scale, a crease side of 0 or 1.
Proxy get_proxy(Reader& r, ProxyKind kind);
/// Reads a sphere (`what` names it in messages), checked: finite, radius >= 0.
Sphere get_sphere(Reader& r, const char* what);

/// Reads a one-byte enumeration value below `count` (`what` names it in messages).
template <class E>
E get_enum(Reader& r, std::uint8_t count, const char* what) {
  const std::size_t at = r.pos();
  const auto v = r.get<std::uint8_t>(what);
  if (v >= count) r.fail_at(at, "unknown " + std::string(what) + " " + std::to_string(v));
  return static_cast<E>(v);
}

}  // namespace clustersurf::detail
