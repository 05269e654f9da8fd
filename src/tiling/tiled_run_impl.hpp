#pragma once
// What a TiledRun holds: its directory and partition, and the paths of its files.

#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/tiling/tiled_run.hpp>

#include "tiling/tiled_run_files.hpp"

#include <filesystem>
#include <string>

namespace clustersurf {

struct TiledRun::Impl {
  std::filesystem::path dir;
  detail::PartitionRecord record;

  std::filesystem::path file(std::string_view name, std::int32_t region, std::string_view ext) const {
    return detail::region_file(dir, name, region, ext);
  }
  void check(std::int32_t region) const {
    if (region < 0 || static_cast<std::size_t>(region) >= record.plan.regions())
      throw OptionError("region " + std::to_string(region) + " is not in the plan (it has " +
                        std::to_string(record.plan.regions()) + ")");
  }
  /// A stage's input file, or InputError saying which stage must run first.
  std::filesystem::path need(const std::filesystem::path& f, const char* stage) const {
    if (!std::filesystem::exists(f)) throw InputError(f, {}, std::string("missing: run ") + stage + " first");
    return f;
  }
  ClusterTree merged_tree() const { return load_tree(need(dir / "tree.cstree", "the merge")); }
  RegionMerge merge_record() const { return detail::read_merge(need(dir / "merge.txt", "the merge")); }
  /// How a region's build oriented its tree, and whether the region is empty.
  OrientationReport orientation(std::int32_t region, std::uint8_t& empty) const {
    bool none = false;
    OrientationReport o =
        detail::read_orientation(need(file("orientation", region, "txt"), "every region's build"), none);
    empty = none ? 1 : 0;
    return o;
  }
  /// A region's tree as its build wrote it (empty for an empty region).
  ClusterTree region_tree(std::int32_t region) const {
    bool empty = false;
    detail::read_orientation(need(file("orientation", region, "txt"), "every region's build"), empty);
    return empty ? ClusterTree{} : load_tree(need(file("tree", region, "cstree"), "every region's build"));
  }
};

}  // namespace clustersurf
