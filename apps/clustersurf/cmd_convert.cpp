#include "commands.hpp"
#include "input.hpp"

#include <clustersurf/spatial/resample.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <iostream>

namespace clustersurf::cli {

int run_convert(Console& console, const ConvertArgs& args) {
  PointCloud cloud = read_input(console, args.input);
  const auto read = cloud.size();
  if (args.voxel) cloud = voxel_downsample(cloud, *args.voxel);
  if (args.subsample) cloud = subsample(cloud, *args.subsample, args.seed);
  PlyWriteOptions ply;
  ply.binary = !args.ascii;
  ply.double_precision = args.double_precision;
  write_point_cloud(args.output, cloud, ply);
  if (console.options().json) {
    std::cout << nlohmann::json{{"input", args.input.file},
                                {"output", args.output},
                                {"points_read", read},
                                {"points", cloud.size()}}
                     .dump(2)
              << "\n";
  } else {
    console.print(fmt::format("wrote {} points to {} (read {})", cloud.size(), args.output, read));
  }
  return 0;
}

}  // namespace clustersurf::cli
