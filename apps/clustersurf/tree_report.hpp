#pragma once
// The description of a cluster tree shared by `info` and `reconstruct`: text lines and JSON.

#include <clustersurf/cluster/cluster_tree.hpp>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace clustersurf::cli {

/// The library's report of the tree (tree_info_json()), as JSON to add to.
nlohmann::json tree_report_json(const ClusterTree& tree);
/// The same as human-readable lines.
std::vector<std::string> tree_report_lines(const ClusterTree& tree);

}  // namespace clustersurf::cli
