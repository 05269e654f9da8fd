#pragma once
// Every public header of clustersurf, by library part: a folder per part (src/ and
// include/clustersurf/ alike), each part including only the parts below it. Link
// clustersurf::clustersurf for all of it, or only the part a program uses (docs/architecture.md,
// "Using the library"): clustersurf::tree builds and saves trees without OpenVDB or Embree.

#include <clustersurf/version.hpp>

// the readers and writers (clustersurf::io)
#include <clustersurf/core/closest_point.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/core/option_spec.hpp>
#include <clustersurf/core/point_cloud.hpp>
#include <clustersurf/core/progress.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/io/point_stream.hpp>
#include <clustersurf/io/surface_sampling.hpp>

// points, proxies, the tree, its implicit surface and its regions (clustersurf::tree)
#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/cluster/noise.hpp>
#include <clustersurf/cluster/noise_field.hpp>
#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/proxy/moments.hpp>
#include <clustersurf/proxy/proxy.hpp>
#include <clustersurf/regions/regions.hpp>
#include <clustersurf/spatial/cloud_index.hpp>
#include <clustersurf/spatial/cloud_stats.hpp>
#include <clustersurf/spatial/kd_tree.hpp>
#include <clustersurf/spatial/normal_estimation.hpp>
#include <clustersurf/spatial/outliers.hpp>
#include <clustersurf/spatial/resample.hpp>
#include <clustersurf/surface/box_walk.hpp>
#include <clustersurf/surface/closed_surface.hpp>
#include <clustersurf/surface/implicit_surface.hpp>
#include <clustersurf/surface/orientation.hpp>
#include <clustersurf/surface/palette.hpp>

// meshing, the pipeline and its tiled runs (clustersurf::mesh)
#include <clustersurf/mesh/mesh_check.hpp>
#include <clustersurf/mesh/mesh_coarsening.hpp>
#include <clustersurf/mesh/mesh_colors.hpp>
#include <clustersurf/mesh/mesh_decimation.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/mesh/mesh_trim.hpp>
#include <clustersurf/mesh/vertex_refit.hpp>
#include <clustersurf/pipeline/option_schema.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>
#include <clustersurf/tiling/tiled_run.hpp>

// pictures (clustersurf::render)
#include <clustersurf/render/camera.hpp>
#include <clustersurf/render/image.hpp>
#include <clustersurf/render/render.hpp>
#include <clustersurf/render/render_option_schema.hpp>

// benchmark inputs and scores (clustersurf::evaluation)
#include <clustersurf/evaluation/mesh_distance.hpp>
#include <clustersurf/evaluation/range_scan.hpp>
#include <clustersurf/evaluation/surface_comparison.hpp>

// the HTML viewer (clustersurf::viewer)
#include <clustersurf/view/html_viewer.hpp>
