#include "commands.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/evaluation/range_scan.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/io/surface_sampling.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <iostream>

namespace clustersurf::cli {

int run_sample(Console& console, const SampleArgs& args) {
  ReadOptions read;
  read.warn = [&console](const std::string& message) { console.warn(message); };
  const TriangleMesh mesh = read_triangle_mesh(args.mesh, read);
  if (mesh.triangles.rows() == 0) throw InputError(args.mesh, {}, "the file has no triangles to sample");
  PointCloud cloud;
  if (args.scanner > 0) {
    if (args.outliers > 0) throw OptionError("--outliers is for area-uniform samples, not --scanner");
    RangeScanOptions options;
    options.scans = args.scanner;
    options.count = args.count;
    options.noise = args.noise;
    options.registration = args.registration;
    options.noise_correlation = args.noise_correlation;
    options.flipped_normals = args.flipped_normals;
    options.distance = args.scanner_distance;
    options.seed = args.seed;
    cloud = scan_surface(mesh, options);
  } else {
    if (args.flipped_normals > 0) throw OptionError("--flip-normals is for --scanner");
    if (args.noise_correlation > 0) throw OptionError("--noise-correlation is for --scanner");
    SurfaceSamplingOptions options;
    options.count = args.count;
    options.noise = args.noise;
    options.outliers = args.outliers;
    options.seed = args.seed;
    cloud = sample_surface(mesh, options);
  }
  if (args.no_normals) cloud.normals.resize(0, 3);
  PlyWriteOptions ply;
  ply.binary = !args.ascii;
  write_point_cloud(args.output, cloud, ply);
  if (console.options().json) {
    std::cout << nlohmann::json{{"mesh", args.mesh},
                                {"output", args.output},
                                {"points", cloud.size()},
                                {"noise", args.noise},
                                {"outliers", args.outliers},
                                {"seed", args.seed},
                                {"scanner", args.scanner},
                                {"registration", args.registration},
                                {"noise_correlation", args.noise_correlation},
                                {"flipped_normals", args.flipped_normals}}
                     .dump(2)
              << "\n";
  } else {
    console.print(
        fmt::format("wrote {} points {} {} to {}", cloud.size(),
                    args.scanner > 0 ? fmt::format("scanned from {} viewpoints of", args.scanner) : "sampled from",
                    args.mesh, args.output));
  }
  return 0;
}

}  // namespace clustersurf::cli
