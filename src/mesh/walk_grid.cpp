#include "mesh/walk_grid.hpp"

#include <openvdb/openvdb.h>

#include <tbb/parallel_for.h>

#include <atomic>
#include <stdexcept>

namespace clustersurf::detail {

namespace {

openvdb::Coord coord(const GridIndex& g) { return openvdb::Coord(g[0], g[1], g[2]); }

}  // namespace

struct WalkGrid::Impl {
  // The corners' values: a voxel is active once its corner is queued.
  openvdb::FloatGrid::Ptr corners = openvdb::FloatGrid::create(0.0f);
  openvdb::MaskGrid::Ptr cells = openvdb::MaskGrid::create();
  openvdb::FloatGrid::Accessor corner_access = corners->getAccessor();
  openvdb::MaskGrid::Accessor cell_access = cells->getAccessor();
};

WalkGrid::WalkGrid() : impl_(std::make_unique<Impl>()) {}
WalkGrid::~WalkGrid() = default;

bool WalkGrid::queue(const GridIndex& corner) {
  const openvdb::Coord c = coord(corner);
  if (impl_->corner_access.isValueOn(c)) return false;
  impl_->corner_access.setValueOn(c);
  return true;
}

void WalkGrid::set_value(const GridIndex& corner, float value) {
  impl_->corner_access.setValueOnly(coord(corner), value);
}

void WalkGrid::values(std::span<SurfaceCell> cells) const {
  std::atomic<bool> unqueued = false;
  const openvdb::FloatGrid& corners = *impl_->corners;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.size(), 4096), [&](const auto& r) {
    const openvdb::FloatGrid::ConstAccessor access = corners.getConstAccessor();
    for (std::size_t t = r.begin(); t != r.end(); ++t) {
      SurfaceCell& cell = cells[t];
      for (std::size_t c = 0; c < 8; ++c) {
        const openvdb::Coord at(cell.corner[0] + kCellCorner[c][0], cell.corner[1] + kCellCorner[c][1],
                                cell.corner[2] + kCellCorner[c][2]);
        if (!access.probeValue(at, cell.values[c])) unqueued = true;
      }
    }
  });
  if (unqueued) throw std::logic_error("mesh walk: a corner read before it was queued");
}

bool WalkGrid::visit(const GridIndex& cell) {
  const openvdb::Coord c = coord(cell);
  if (impl_->cell_access.isValueOn(c)) return false;
  impl_->cell_access.setValueOn(c);
  return true;
}

std::size_t WalkGrid::queued() const { return static_cast<std::size_t>(impl_->corners->activeVoxelCount()); }

}  // namespace clustersurf::detail
