// Point-cloud input and output throughput. One cloud of 1,000,000 points (near a bumpy sphere,
// float-exact values, unit normals) is written once, in a temporary folder (removed at exit), in
// every input format the library reads:
//   - binary PLY (float xyz and normals, the common scanner layout) and ascii PLY;
//   - LAS 1.2 point format 3 (34-byte records: int32 xyz at scale 1e-6 plus an offset,
//     intensity, RGB) and LAS 1.4 point format 6 (30-byte records, no colour);
//   - PCD with float x y z normal_x normal_y normal_z: binary, binary_compressed (LZF, fields
//     one after another, as PCL writes it) and ascii;
//   - PTX: one scan, a columns x rows grid, identity transform, "x y z intensity" lines;
//   - E57: one scan, double-precision Float cartesianX/Y/Z and a single-precision intensity,
//     packets of at most 64 KiB, 1024-byte pages with their CRC-32C (tests/e57_writer.hpp).
// It times read_point_cloud on each file, write_ply of the cloud, and write_triangle_mesh of a
// torus grid of 1,000,000 triangles (with vertex normals) as GLB and STL. Reads run from the
// page cache, so they measure parsing, not the disk.
//
//   bench_io [--benchmark_filter=...] [--points=N]

#include <clustersurf/io/point_cloud_io.hpp>

#ifdef CLUSTERSURF_BENCH_E57
#include "e57_writer.hpp"
#endif

#include <benchmark/benchmark.h>
#include <lzf.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace clustersurf;

/// A generated input file and its size.
struct Input {
  fs::path path;
  std::size_t bytes = 0;
};

/// Stores `v`'s bytes (little-endian host) at `s[at]`.
template <class T>
void put(std::string& s, std::size_t at, T v) {
  std::memcpy(s.data() + at, &v, sizeof(T));
}

/// Appends the shortest decimal that reads back as `v`.
void append_float(std::string& s, float v) {
  char b[32];
  const auto r = std::to_chars(b, b + sizeof b, v);
  s.append(b, r.ptr);
}

void write_bytes(const fs::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

/// The cloud's intensity for the scanner formats: a function of the normal, in [0, 1].
float intensity_of(const PointCloud& c, Eigen::Index i) { return static_cast<float>(0.5 * (c.normals(i, 2) + 1.0)); }

/// LAS 1.2 point format 3 (34-byte records with RGB) or LAS 1.4 point format 6 (30 bytes):
/// coordinates as int32 at scale 1e-6 plus an offset, intensity, 16-bit colours from the normals.
std::string las_file(const PointCloud& c, bool v14) {
  const auto n = static_cast<std::size_t>(c.size());
  const std::size_t header = v14 ? 375 : 227, record = v14 ? 30 : 34;
  const double scale = 1e-6, offset[3] = {-0.125, -0.25, 0.5};
  std::string s(header + n * record, '\0');
  s.replace(0, 4, "LASF");
  if (v14) put<std::uint16_t>(s, 6, 0x10);  // global encoding: WKT (required by formats 6-10)
  s[24] = 1;
  s[25] = v14 ? 4 : 2;
  const std::string software = "clustersurf bench_io";
  s.replace(58, software.size(), software);
  put<std::uint16_t>(s, 94, static_cast<std::uint16_t>(header));
  put<std::uint32_t>(s, 96, static_cast<std::uint32_t>(header));  // no VLRs
  s[104] = static_cast<char>(v14 ? 6 : 3);
  put<std::uint16_t>(s, 105, static_cast<std::uint16_t>(record));
  put<std::uint32_t>(s, 107, v14 ? 0U : static_cast<std::uint32_t>(n));  // legacy counts: 0 for formats 6-10
  put<std::uint32_t>(s, 111, v14 ? 0U : static_cast<std::uint32_t>(n));
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (std::size_t i = 0; i < n; ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    char* r = s.data() + header + i * record;
    for (int k = 0; k < 3; ++k) {
      const auto q = static_cast<std::int32_t>(std::lround((c.positions(row, k) - offset[k]) / scale));
      std::memcpy(r + 4 * k, &q, 4);
      lo(k) = std::min(lo(k), q * scale + offset[k]);
      hi(k) = std::max(hi(k), q * scale + offset[k]);
    }
    const auto intensity = static_cast<std::uint16_t>(std::lround(intensity_of(c, row) * 65535.0));
    std::memcpy(r + 12, &intensity, 2);
    if (v14) {
      r[14] = 0x11;  // return 1 of 1
      r[16] = 1;     // classification: unclassified
    } else {
      r[14] = 0x09;  // return 1 of 1
      r[15] = 1;
      for (int k = 0; k < 3; ++k) {
        const auto color = static_cast<std::uint16_t>(std::lround(0.5 * (c.normals(row, k) + 1.0) * 65535.0));
        std::memcpy(r + 28 + 2 * k, &color, 2);
      }
    }
  }
  for (int k = 0; k < 3; ++k) {
    put<double>(s, 131 + 8 * static_cast<std::size_t>(k), scale);
    put<double>(s, 155 + 8 * static_cast<std::size_t>(k), offset[k]);
    put<double>(s, 179 + 16 * static_cast<std::size_t>(k), hi(k));
    put<double>(s, 187 + 16 * static_cast<std::size_t>(k), lo(k));
  }
  if (v14) {
    put<std::uint64_t>(s, 247, n);
    put<std::uint64_t>(s, 255, n);  // all are first returns
  }
  return s;
}

/// PCD 0.7 with float x y z normal_x normal_y normal_z; `data` is ascii, binary or
/// binary_compressed (LZF of the fields one after another, with the two sizes before it).
std::string pcd_file(const PointCloud& c, const std::string& data) {
  const auto n = static_cast<std::size_t>(c.size());
  std::string s =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\n"
      "SIZE 4 4 4 4 4 4\nTYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH " +
      std::to_string(n) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(n) + "\nDATA " + data + "\n";
  const auto value = [&](std::size_t i, int f) {
    const auto row = static_cast<Eigen::Index>(i);
    return static_cast<float>(f < 3 ? c.positions(row, f) : c.normals(row, f - 3));
  };
  if (data == "ascii") {
    for (std::size_t i = 0; i < n; ++i)
      for (int f = 0; f < 6; ++f) append_float(s, value(i, f)), s.push_back(f < 5 ? ' ' : '\n');
    return s;
  }
  std::vector<float> raw(6 * n);
  const bool field_major = data == "binary_compressed";
  for (std::size_t i = 0; i < n; ++i)
    for (int f = 0; f < 6; ++f)
      raw[field_major ? static_cast<std::size_t>(f) * n + i : 6 * i + static_cast<std::size_t>(f)] = value(i, f);
  const auto raw_bytes = static_cast<unsigned>(raw.size() * sizeof(float));
  if (!field_major) return s.append(reinterpret_cast<const char*>(raw.data()), raw_bytes);
  std::string packed(raw_bytes + raw_bytes / 16 + 64, '\0');
  const unsigned size = lzf_compress(raw.data(), raw_bytes, packed.data(), static_cast<unsigned>(packed.size()));
  if (size == 0) throw std::runtime_error("lzf_compress failed");
  s.append(8, '\0');
  put<std::uint32_t>(s, s.size() - 8, size);
  put<std::uint32_t>(s, s.size() - 4, raw_bytes);
  return s.append(packed, 0, size);
}

/// PTX: one scan of columns x rows (n's divisor nearest below its square root), scanner at
/// zero with the identity axes and transform, "x y z intensity" lines.
std::string ptx_file(const PointCloud& c) {
  const auto n = static_cast<std::size_t>(c.size());
  auto columns = static_cast<std::size_t>(std::sqrt(static_cast<double>(n)));
  while (columns > 1 && n % columns != 0) --columns;
  std::string s = std::to_string(columns) + "\n" + std::to_string(n / columns) +
                  "\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  for (std::size_t i = 0; i < n; ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    for (int k = 0; k < 3; ++k) append_float(s, static_cast<float>(c.positions(row, k))), s.push_back(' ');
    append_float(s, intensity_of(c, row));
    s.push_back('\n');
  }
  return s;
}

#ifdef CLUSTERSURF_BENCH_E57
/// E57: one scan, double-precision cartesianX/Y/Z and a single-precision intensity in [0, 1].
std::string e57_file(const PointCloud& c) {
  std::vector<double> xyz[3], intensity;
  for (Eigen::Index i = 0; i < c.size(); ++i) {
    for (int k = 0; k < 3; ++k) xyz[k].push_back(c.positions(i, k));
    intensity.push_back(intensity_of(c, i));
  }
  using namespace clustersurf::test;
  const TestScan scan{{float_field("cartesianX", xyz[0]), float_field("cartesianY", xyz[1]),
                       float_field("cartesianZ", xyz[2]), float_field("intensity", intensity, true)},
                      "<intensityLimits type=\"Structure\"><intensityMinimum type=\"Float\">0</intensityMinimum>"
                      "<intensityMaximum type=\"Float\">1</intensityMaximum></intensityLimits>"};
  WriteOptions o;
  o.chunk = 1 << 16;  // as much as fits a 64 KiB packet
  return write_e57({scan}, o).bytes;
}
#endif

/// A torus grid of `2 * rings * segments` triangles with unit vertex normals.
TriangleMesh torus(int rings, int segments) {
  TriangleMesh m;
  m.vertices.resize(static_cast<Eigen::Index>(rings) * segments, 3);
  m.normals.resize(m.vertices.rows(), 3);
  m.triangles.resize(2 * m.vertices.rows(), 3);
  const double big = 1.0, small = 0.3;
  const auto at = [&](int r, int s) { return static_cast<std::int32_t>((r % rings) * segments + s % segments); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double u = 2 * std::numbers::pi * r / rings, v = 2 * std::numbers::pi * s / segments;
      const Eigen::Vector3d normal(std::cos(u) * std::cos(v), std::sin(u) * std::cos(v), std::sin(v));
      const Eigen::Index i = at(r, s);
      m.normals.row(i) = normal.transpose();
      m.vertices.row(i) = (Eigen::Vector3d(big * std::cos(u), big * std::sin(u), 0) + small * normal).transpose();
      m.triangles.row(2 * i) << at(r, s), at(r + 1, s), at(r + 1, s + 1);
      m.triangles.row(2 * i + 1) << at(r, s), at(r + 1, s + 1), at(r, s + 1);
    }
  return m;
}

struct Files {
  fs::path dir;
  PointCloud cloud;
  TriangleMesh mesh;
  Input binary_ply, ascii_ply, las12, las14, pcd_binary, pcd_compressed, pcd_ascii, ptx, e57;

  explicit Files(Eigen::Index n) {
    std::string pattern = (fs::temp_directory_path() / "clustersurf-bench-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    dir = pattern;
    // Points near a bumpy sphere, with unit normals; values rounded to float so the binary
    // file holds exactly the cloud.
    std::mt19937_64 rng(1);
    std::normal_distribution<double> g(0.0, 1.0);
    cloud.positions.resize(n, 3);
    cloud.normals.resize(n, 3);
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::Vector3d u(g(rng), g(rng), g(rng));
      u.normalize();
      const double r = 0.1 * (1.0 + 0.05 * std::sin(7 * u.x()) * std::cos(5 * u.y()));
      cloud.positions.row(i) = (r * u).cast<float>().cast<double>().transpose();
      cloud.normals.row(i) = u.cast<float>().cast<double>().transpose();
    }
    binary_ply.path = dir / "cloud_binary.ply";
    ascii_ply.path = dir / "cloud_ascii.ply";
    write_ply(binary_ply.path, cloud);
    PlyWriteOptions ascii;
    ascii.binary = false;
    write_ply(ascii_ply.path, cloud, ascii);
    const auto make = [&](Input& in, const char* name, const std::string& bytes) {
      in.path = dir / name;
      write_bytes(in.path, bytes);
    };
    make(las12, "cloud_1.2.las", las_file(cloud, false));
    make(las14, "cloud_1.4.las", las_file(cloud, true));
    make(pcd_binary, "cloud_binary.pcd", pcd_file(cloud, "binary"));
    make(pcd_compressed, "cloud_compressed.pcd", pcd_file(cloud, "binary_compressed"));
    make(pcd_ascii, "cloud_ascii.pcd", pcd_file(cloud, "ascii"));
    make(ptx, "cloud.ptx", ptx_file(cloud));
#ifdef CLUSTERSURF_BENCH_E57
    make(e57, "cloud.e57", e57_file(cloud));
#endif
    for (Input* in : inputs())
      if (!in->path.empty()) in->bytes = fs::file_size(in->path);
    mesh = torus(1000, 500);
  }
  ~Files() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::vector<Input*> inputs() {
    return {&binary_ply, &ascii_ply, &las12, &las14, &pcd_binary, &pcd_compressed, &pcd_ascii, &ptx, &e57};
  }
};

Files* files = nullptr;

void read_file(benchmark::State& state, const Input& in) {
  Eigen::Index points = 0;
  for (auto _ : state) {
    PointCloud c = read_point_cloud(in.path);
    points = c.size();
    benchmark::DoNotOptimize(c.positions.data());
  }
  if (points != files->cloud.size()) state.SkipWithError("wrong point count");
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(in.bytes));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * points);
  state.counters["file_MB"] = static_cast<double>(in.bytes) / 1e6;
}

void BM_ReadBinaryPly(benchmark::State& state) { read_file(state, files->binary_ply); }
void BM_ReadAsciiPly(benchmark::State& state) { read_file(state, files->ascii_ply); }
void BM_ReadLas12Format3(benchmark::State& state) { read_file(state, files->las12); }
void BM_ReadLas14Format6(benchmark::State& state) { read_file(state, files->las14); }
void BM_ReadBinaryPcd(benchmark::State& state) { read_file(state, files->pcd_binary); }
void BM_ReadCompressedPcd(benchmark::State& state) { read_file(state, files->pcd_compressed); }
void BM_ReadAsciiPcd(benchmark::State& state) { read_file(state, files->pcd_ascii); }
void BM_ReadPtx(benchmark::State& state) { read_file(state, files->ptx); }
#ifdef CLUSTERSURF_BENCH_E57
void BM_ReadE57(benchmark::State& state) { read_file(state, files->e57); }
#endif

void BM_WriteBinaryPly(benchmark::State& state) {
  const fs::path out = files->dir / "written.ply";
  for (auto _ : state) write_ply(out, files->cloud);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(fs::file_size(out)));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * files->cloud.size());
}

/// write_triangle_mesh of the torus to `name` (format by extension); items are triangles.
void write_mesh(benchmark::State& state, const char* name) {
  const fs::path out = files->dir / name;
  for (auto _ : state) write_triangle_mesh(out, files->mesh);
  const auto bytes = static_cast<std::int64_t>(fs::file_size(out));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * bytes);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * files->mesh.triangles.rows());
  state.counters["file_MB"] = static_cast<double>(bytes) / 1e6;
}
void BM_WriteGlb(benchmark::State& state) { write_mesh(state, "written.glb"); }
void BM_WriteStl(benchmark::State& state) { write_mesh(state, "written.stl"); }

BENCHMARK(BM_ReadBinaryPly)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_ReadAsciiPly)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_ReadLas12Format3)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_ReadLas14Format6)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_ReadBinaryPcd)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_ReadCompressedPcd)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_ReadAsciiPcd)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_ReadPtx)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
#ifdef CLUSTERSURF_BENCH_E57
BENCHMARK(BM_ReadE57)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
#endif
BENCHMARK(BM_WriteBinaryPly)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_WriteGlb)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_WriteStl)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

}  // namespace

int main(int argc, char** argv) {
  Eigen::Index n = 1'000'000;
  // Our own flag, removed before Google Benchmark sees the arguments.
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--points=", 0) == 0)
      n = std::stol(arg.substr(9));
    else
      argv[kept++] = argv[i];
  }
  argc = kept;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  Files f(n);
  files = &f;
  benchmark::AddCustomContext("points", std::to_string(n));
  benchmark::AddCustomContext("mesh_triangles", std::to_string(f.mesh.triangles.rows()));
  const std::pair<const char*, const Input*> sizes[] = {{"binary_ply_bytes", &f.binary_ply},
                                                        {"ascii_ply_bytes", &f.ascii_ply},
                                                        {"las_1.2_bytes", &f.las12},
                                                        {"las_1.4_bytes", &f.las14},
                                                        {"pcd_binary_bytes", &f.pcd_binary},
                                                        {"pcd_compressed_bytes", &f.pcd_compressed},
                                                        {"pcd_ascii_bytes", &f.pcd_ascii},
                                                        {"ptx_bytes", &f.ptx},
                                                        {"e57_bytes", &f.e57}};
  for (const auto& [name, in] : sizes)
    if (in->bytes > 0) benchmark::AddCustomContext(name, std::to_string(in->bytes));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  files = nullptr;
  return 0;
}
