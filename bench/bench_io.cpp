// Point-cloud input and output throughput: reading a 1,000,000-point binary PLY (float xyz and
// normals, the common scanner layout), the same cloud as ascii PLY, and writing binary PLY.
// The files are generated once in a temporary folder (removed at exit); reads run from the page
// cache, so they measure parsing, not the disk.
//
//   bench_io [--benchmark_filter=...] [--points=N]

#include <clustersurf/point_cloud_io.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using namespace clustersurf;

struct Files {
  fs::path dir;
  fs::path binary_ply;
  fs::path ascii_ply;
  PointCloud cloud;
  std::size_t binary_bytes = 0;
  std::size_t ascii_bytes = 0;

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
    binary_ply = dir / "cloud_binary.ply";
    ascii_ply = dir / "cloud_ascii.ply";
    write_ply(binary_ply, cloud);
    PlyWriteOptions ascii;
    ascii.binary = false;
    write_ply(ascii_ply, cloud, ascii);
    binary_bytes = fs::file_size(binary_ply);
    ascii_bytes = fs::file_size(ascii_ply);
  }
  ~Files() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

Files* files = nullptr;

void read_file(benchmark::State& state, const fs::path& file, std::size_t bytes) {
  Eigen::Index points = 0;
  for (auto _ : state) {
    PointCloud c = read_point_cloud(file);
    points = c.size();
    benchmark::DoNotOptimize(c.positions.data());
  }
  if (points != files->cloud.size()) state.SkipWithError("wrong point count");
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(bytes));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * points);
  state.counters["file_MB"] = static_cast<double>(bytes) / 1e6;
}

void BM_ReadBinaryPly(benchmark::State& state) { read_file(state, files->binary_ply, files->binary_bytes); }
void BM_ReadAsciiPly(benchmark::State& state) { read_file(state, files->ascii_ply, files->ascii_bytes); }

void BM_WriteBinaryPly(benchmark::State& state) {
  const fs::path out = files->dir / "written.ply";
  for (auto _ : state) write_ply(out, files->cloud);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(fs::file_size(out)));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * files->cloud.size());
}

BENCHMARK(BM_ReadBinaryPly)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_ReadAsciiPly)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_WriteBinaryPly)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

}  // namespace

int main(int argc, char** argv) {
  Eigen::Index n = 1'000'000;
  // Our own flag, removed before Google Benchmark sees the arguments.
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--points=", 0) == 0) n = std::stol(arg.substr(9));
    else argv[kept++] = argv[i];
  }
  argc = kept;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  Files f(n);
  files = &f;
  benchmark::AddCustomContext("points", std::to_string(n));
  benchmark::AddCustomContext("binary_ply_bytes", std::to_string(f.binary_bytes));
  benchmark::AddCustomContext("ascii_ply_bytes", std::to_string(f.ascii_bytes));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  files = nullptr;
  return 0;
}
