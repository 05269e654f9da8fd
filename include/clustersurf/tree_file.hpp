#pragma once
// The .cstree file: a versioned, checksummed binary image of a ClusterTree
// (docs/file-format.md). Saving is deterministic: the same tree gives the same bytes.

#include <clustersurf/cluster_tree.hpp>

#include <filesystem>
#include <string>

namespace clustersurf {

/// Current version of the format written by save_tree(). Version 2 added the input's point
/// spacing and each node's cluster extent; version-1 files still load (spacing 0, extent
/// support radius / alpha).
inline constexpr std::uint32_t kTreeFileVersion = 2;

/// The file's bytes for `tree`.
std::string serialize_tree(const ClusterTree& tree);
/// Parses and validates bytes produced by serialize_tree() (any version up to the current); `file` names them in errors.
/// Throws InputError (with the byte offset) on any corruption or inconsistency.
ClusterTree deserialize_tree(std::string_view bytes, const std::filesystem::path& file = "<memory>");

/// Writes the tree atomically. Throws IoError.
void save_tree(const std::filesystem::path& file, const ClusterTree& tree);
/// Reads and validates a tree file. Throws IoError or InputError.
ClusterTree load_tree(const std::filesystem::path& file);

}  // namespace clustersurf
