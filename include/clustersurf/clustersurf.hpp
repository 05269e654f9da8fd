#pragma once
// Every public header of clustersurf. Link clustersurf::clustersurf for all of it, or only the
// part a program uses (docs/architecture.md, "Using the library"): clustersurf::tree builds and
// saves trees without OpenVDB or Embree.

#include <clustersurf/version.hpp>

// io and errors (clustersurf::io)
#include <clustersurf/errors.hpp>
#include <clustersurf/point_cloud.hpp>
#include <clustersurf/point_cloud_io.hpp>
#include <clustersurf/progress.hpp>
#include <clustersurf/point_stream.hpp>
#include <clustersurf/tiled_run.hpp>
#include <clustersurf/tiling.hpp>
#include <clustersurf/tree_file.hpp>

// points, proxies, the tree and its implicit surface (clustersurf::tree)
#include <clustersurf/cloud_stats.hpp>
#include <clustersurf/normal_estimation.hpp>
#include <clustersurf/cluster_tree.hpp>
#include <clustersurf/implicit_surface.hpp>
#include <clustersurf/closed_surface.hpp>
#include <clustersurf/kd_tree.hpp>
#include <clustersurf/moments.hpp>
#include <clustersurf/noise.hpp>
#include <clustersurf/orientation.hpp>
#include <clustersurf/outliers.hpp>
#include <clustersurf/palette.hpp>
#include <clustersurf/proxy.hpp>
#include <clustersurf/resample.hpp>

// meshing and the pipeline (clustersurf::mesh)
#include <clustersurf/mesh_colors.hpp>
#include <clustersurf/mesh_extraction.hpp>
#include <clustersurf/mesh_trim.hpp>
#include <clustersurf/mesh_decimation.hpp>
#include <clustersurf/reconstruct.hpp>

// pictures (clustersurf::render)
#include <clustersurf/camera.hpp>
#include <clustersurf/image.hpp>
#include <clustersurf/render.hpp>

// benchmark inputs and scores (clustersurf::evaluation)
#include <clustersurf/mesh_distance.hpp>
#include <clustersurf/mesh_check.hpp>
#include <clustersurf/range_scan.hpp>
#include <clustersurf/surface_comparison.hpp>
#include <clustersurf/surface_sampling.hpp>

// the HTML viewer (clustersurf::viewer)
#include <clustersurf/html_viewer.hpp>
