#include "mesh/walk_grid.hpp"

#include <openvdb/openvdb.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace clustersurf::detail {

namespace {

openvdb::Coord coord(const GridIndex& g) { return openvdb::Coord(g[0], g[1], g[2]); }

}  // namespace

struct WalkGrid::Impl {
  // The corners' ids: a voxel is active once its corner is queued; its value by id.
  openvdb::Int32Grid::Ptr corners = openvdb::Int32Grid::create(-1);
  openvdb::MaskGrid::Ptr cells = openvdb::MaskGrid::create();
  openvdb::Int32Grid::Accessor corner_access = corners->getAccessor();
  openvdb::MaskGrid::Accessor cell_access = cells->getAccessor();
  std::vector<float> values;  ///< by id; NaN until set
  std::size_t set = 0;        ///< ids below it have their values
};

WalkGrid::WalkGrid() : impl_(std::make_unique<Impl>()) {}
WalkGrid::~WalkGrid() = default;

bool WalkGrid::queue(const GridIndex& corner) {
  const openvdb::Coord c = coord(corner);
  if (impl_->corner_access.isValueOn(c)) return false;
  impl_->corner_access.setValueOn(c, static_cast<std::int32_t>(impl_->values.size()));
  impl_->values.push_back(std::numeric_limits<float>::quiet_NaN());
  return true;
}

void WalkGrid::set_values(std::span<const float> values) {
  if (values.size() != impl_->values.size() - impl_->set)
    throw std::logic_error("mesh walk: values for " + std::to_string(values.size()) + " corners, " +
                           std::to_string(impl_->values.size() - impl_->set) + " queued");
  std::copy(values.begin(), values.end(), impl_->values.begin() + static_cast<std::ptrdiff_t>(impl_->set));
  impl_->set = impl_->values.size();
}

void WalkGrid::values(std::span<SurfaceCell> cells) const {
  std::atomic<bool> unqueued = false;
  const openvdb::Int32Grid& corners = *impl_->corners;
  const std::vector<float>& values = impl_->values;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.size(), 4096), [&](const auto& r) {
    const openvdb::Int32Grid::ConstAccessor access = corners.getConstAccessor();
    for (std::size_t t = r.begin(); t != r.end(); ++t) {
      SurfaceCell& cell = cells[t];
      for (std::size_t c = 0; c < 8; ++c) {
        const openvdb::Coord at(cell.corner[0] + kCellCorner[c][0], cell.corner[1] + kCellCorner[c][1],
                                cell.corner[2] + kCellCorner[c][2]);
        std::int32_t id = -1;
        if (access.probeValue(at, id))
          cell.values[c] = values[static_cast<std::size_t>(id)];
        else
          unqueued = true;
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

std::size_t WalkGrid::queued() const { return impl_->values.size(); }

}  // namespace clustersurf::detail
