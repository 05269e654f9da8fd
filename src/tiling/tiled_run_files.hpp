#pragma once
// The files of a tiled run's work directory: names, and the small text and binary formats the
// tasks exchange (plan, surveys, orientations, tiles). Every file is written atomically.

#include <clustersurf/surface/orientation.hpp>
#include <clustersurf/tiling/tiled_run.hpp>

#include "tiling/tiles.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace clustersurf::detail {

/// What plan.txt holds: the partition and the input it came from.
struct PartitionRecord {
  std::uintmax_t input_size = 0;
  std::int64_t input_mtime = 0;  ///< nanoseconds since the file clock's epoch
  std::uint64_t max_points = 0;
  double halo_spacings = 0;
  std::uint64_t input_points = 0;
  bool normals = false;
  bool colors = false;  ///< the region files hold each point's color (pack_color()) after its normal
  UpAxis up = UpAxis::Y;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  RegionPlan plan;
  std::vector<std::uint64_t> own, halo;  ///< points in each region's files
};

/// Doubles per point in a region file: the position, the normal when the input has normals, and
/// the color (pack_color()) when it has colors.
inline std::size_t region_record_values(const PartitionRecord& r) {
  return 3 + (r.normals ? 3 : 0) + (r.colors ? 1 : 0);
}

/// An 8-bit RGB color as one double, exactly: red * 65536 + green * 256 + blue.
inline double pack_color(const Eigen::Matrix<std::uint8_t, 1, 3>& c) { return c(0) * 65536.0 + c(1) * 256.0 + c(2); }
/// The color pack_color() packed (values outside its range clamped to it).
inline Eigen::Matrix<std::uint8_t, 1, 3> unpack_color(double packed) {
  const auto v = static_cast<std::uint32_t>(std::clamp(packed, 0.0, 16777215.0));
  return {static_cast<std::uint8_t>(v >> 16), static_cast<std::uint8_t>((v >> 8) & 0xFF),
          static_cast<std::uint8_t>(v & 0xFF)};
}

/// "dir/name-000012.ext": a region's file.
std::filesystem::path region_file(const std::filesystem::path& dir, std::string_view name, std::int32_t region,
                                  std::string_view ext);

void write_partition(const std::filesystem::path& file, const PartitionRecord& record);
/// InputError (file, line) when the file is not a plan written by write_partition().
PartitionRecord read_partition(const std::filesystem::path& file);

void write_survey(const std::filesystem::path& file, const RegionSurvey& survey);
RegionSurvey read_survey(const std::filesystem::path& file);

/// A region's orientation report, and whether its tree is empty (no tree file then). Written
/// after the tree file: its presence marks the region's build done.
void write_orientation(const std::filesystem::path& file, const OrientationReport& report, bool empty);
OrientationReport read_orientation(const std::filesystem::path& file, bool& empty);

/// How the merge joined the regions (merge.txt), for the mesh tasks and the join. Written
/// before tree.cstree, whose presence marks the merge done.
void write_merge(const std::filesystem::path& file, const RegionMerge& merge);
/// InputError (file, line) when the file is not a record written by write_merge().
RegionMerge read_merge(const std::filesystem::path& file);

/// A mesh tile in binary: vertices, normals and votes exactly as computed (doubles, floats),
/// its colors when it has them, and its up axis.
void write_tile(const std::filesystem::path& file, const MeshTile& tile);
/// InputError (file, byte) when the file is not a whole tile written by write_tile().
MeshTile read_tile(const std::filesystem::path& file);

/// The record that a directory holds a tiled run (clustersurf-run.txt, written before any
/// other file of the run): how many directory levels the run created, removed again when the
/// run's files are and they are then empty, and how many regions the run's files are named for.
struct RunRecord {
  int created_levels = 0;
  std::uint64_t regions = 0;
};
inline constexpr const char* kRunRecordName = "clustersurf-run.txt";
void write_run_record(const std::filesystem::path& dir, const RunRecord& record);
/// The directory's run record; nullopt when it has none, InputError (file, line) when it is malformed.
std::optional<RunRecord> read_run_record(const std::filesystem::path& dir);

/// Whether a file's name is of the kind a run writes ("plan.txt", "tile-000003.bin", their
/// temporary files ".NAME.tmpXXXXXX"): a directory without a run record that holds one is not
/// taken for a work directory.
bool is_run_file_name(const std::filesystem::path& file);
/// The files of a run of `regions` regions that are in `dir`: exactly the names the run
/// writes, and the temporary files of those writes that a killed task left behind. The run
/// record itself is not among them. Regular files only, never a link. IoError when `dir` cannot be listed.
std::vector<std::filesystem::path> run_files(const std::filesystem::path& dir, std::uint64_t regions);
/// Removes the files; IoError when a removal fails.
void remove_files(const std::vector<std::filesystem::path>& files);

/// The whole file as text; IoError when it cannot be read.
std::string read_text(const std::filesystem::path& file);
/// Writes `text` atomically.
void write_text(const std::filesystem::path& file, std::string_view text);

}  // namespace clustersurf::detail
