#pragma once
// The mesh stage shared by `mesh` and `reconstruct --mesh`: extract, color, write, report.

#include "commands.hpp"

#include <clustersurf/cluster_tree.hpp>

#include <nlohmann/json.hpp>

namespace clustersurf::cli {

/// Meshes `tree` per `args`, writes `output` atomically and returns the figures as JSON
/// (also printed as text unless --json/--quiet). `cloud` (may be null): the tree's input, for --trim and --color distance.
nlohmann::json write_tree_mesh(Console& console, const ClusterTree& tree, const MeshArgs& args, const std::string& output,
                               const PointCloud* cloud);

}  // namespace clustersurf::cli
