#pragma once
// The .cstree file: a versioned, checksummed binary image of a ClusterTree
// (docs/file-format.md). Saving is deterministic: the same tree gives the same bytes.

#include <clustersurf/cluster/cluster_tree.hpp>

#include <filesystem>
#include <string>

namespace clustersurf {

/// Current version of the format written by save_tree(). Version 3 added the input's origin;
/// version 2 the input's point spacing and each node's cluster extent. Older files still load
/// (origin 0; spacing 0 and extent support radius / alpha for version 1).
inline constexpr std::uint32_t kTreeFileVersion = 3;

/// The file's bytes for `tree`.
std::string serialize_tree(const ClusterTree& tree);
/// Parses and validates bytes produced by serialize_tree() (any version up to the current); `file` names them in
/// errors. Throws InputError (with the byte offset) on any corruption or inconsistency.
ClusterTree deserialize_tree(std::string_view bytes, const std::filesystem::path& file = "<memory>");

/// Writes the tree atomically. Throws IoError.
void save_tree(const std::filesystem::path& file, const ClusterTree& tree);
/// Reads and validates a tree file. Throws IoError or InputError.
ClusterTree load_tree(const std::filesystem::path& file);

}  // namespace clustersurf
