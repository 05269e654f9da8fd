// libFuzzer target: the files of a tiled run (plan, survey, orientation, merge record, mesh tile, run record), which a
// worker reads from a directory other machines write to. The first byte picks the reader; the
// rest is the file.

#include "fuzz_checks.hpp"

#include "tiling/tiled_run_files.hpp"

#include <fstream>
#include <optional>
#include <string>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace clustersurf;
  if (size == 0) return 0;
  static const std::string file = (fuzz::scratch_directory() / detail::kRunRecordName).string();
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  try {
    switch (data[0] % 6) {
      case 0: {
        const detail::PartitionRecord r = detail::read_partition(file);
        // A plan that reads is one region_of() can walk: children after parents, leaves naming regions.
        fuzz::require(!r.plan.cells.empty() && r.own.size() == r.plan.regions() && r.halo.size() == r.plan.regions());
        for (std::size_t c = 0; c < r.plan.cells.size(); ++c) {
          const RegionPlan::Cell& cell = r.plan.cells[c];
          fuzz::require(cell.left < 0
                            ? cell.region >= 0 && static_cast<std::size_t>(cell.region) < r.plan.regions()
                            : static_cast<std::size_t>(cell.left) > c && static_cast<std::size_t>(cell.right) > c &&
                                  static_cast<std::size_t>(cell.right) < r.plan.cells.size());
        }
        break;
      }
      case 1:
        detail::read_survey(file);
        break;
      case 2: {
        bool empty = false;
        detail::read_orientation(file, empty);
        break;
      }
      case 3: {
        const RegionMerge m = detail::read_merge(file);
        fuzz::require(m.flipped.size() == m.reach.size());
        break;
      }
      case 5: {
        const std::optional<detail::RunRecord> r = detail::read_run_record(fuzz::scratch_directory());
        fuzz::require(r && r->created_levels >= 0);
        break;
      }
      default: {
        const MeshTile tile = detail::read_tile(file);
        const TriangleMesh& m = tile.mesh;
        fuzz::require(m.normals.rows() == m.vertices.rows() && m.attributes.size() == 1 &&
                      m.attributes[0].values.size() == m.vertices.rows());
        fuzz::require(m.triangles.size() == 0 ||
                      (m.triangles.minCoeff() >= 0 && m.triangles.maxCoeff() < m.vertices.rows()));
      }
    }
  } catch (const InputError&) {}
  return 0;
}
