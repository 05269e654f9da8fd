// The option structs' field lists (for_each_field) against their fields, and the tiled run's
// fingerprint of the options, which walks those lists.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/option_fields.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>
#include <clustersurf/tiling/tiled_run.hpp>

#include "option_leaves.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <type_traits>
#include <vector>

using namespace clustersurf;
using clustersurf::test::for_each_leaf;

namespace {

template <class T>
std::size_t listed_fields() {
  T o{};
  std::size_t n = 0;
  for_each_field(o, [&](std::string_view, auto&) { ++n; });
  return n;
}

/// Another value of the same field.
template <class V>
void change(V& value) {
  if constexpr (std::is_same_v<V, bool>)
    value = !value;
  else if constexpr (std::is_enum_v<V>)
    value = static_cast<V>(static_cast<std::underlying_type_t<V>>(value) + 1);
  else if constexpr (kIsOptional<V>)
    value = value ? typename V::value_type(*value + 1) : typename V::value_type(1);
  else
    value = static_cast<V>(value + 1);
}

}  // namespace

TEST(OptionFields, EveryStructListsEachOfItsFields) {
  EXPECT_EQ(listed_fields<OutlierOptions>(), field_count<OutlierOptions>());
  EXPECT_EQ(listed_fields<NoiseOptions>(), field_count<NoiseOptions>());
  EXPECT_EQ(listed_fields<BuildOptions>(), field_count<BuildOptions>());
  EXPECT_EQ(listed_fields<MeshOptions>(), field_count<MeshOptions>());
  EXPECT_EQ(listed_fields<TrimOptions>(), field_count<TrimOptions>());
  EXPECT_EQ(listed_fields<VertexRefitOptions>(), field_count<VertexRefitOptions>());
  EXPECT_EQ(listed_fields<ClosingOptions>(), field_count<ClosingOptions>());
  EXPECT_EQ(listed_fields<DecimationOptions>(), field_count<DecimationOptions>());
  EXPECT_EQ(listed_fields<SurfaceMeshOptions>(), field_count<SurfaceMeshOptions>());
  EXPECT_EQ(listed_fields<ReconstructOptions>(), field_count<ReconstructOptions>());
}

TEST(OptionFields, FieldCountCountsAnAggregatesFields) {
  struct Three {
    int a = 1;
    std::optional<double> b;
    OutlierOptions c;
  };
  static_assert(field_count<Three>() == 3);
  static_assert(field_count<OutlierOptions>() == 5);
}

TEST(OptionFields, TheFingerprintChangesWithEveryOptionThatDecidesTheStoredResults) {
  const ReconstructOptions defaults;
  const std::string base = options_fingerprint(defaults);
  // The fields that decide nothing a run stores.
  const std::vector<std::string> not_stored = {"mesh", "meshing.grid.memory_limit", "meshing.closing.",
                                               "meshing.decimation.", "meshing.distance_scale"};
  std::size_t leaves = 0;
  {
    ReconstructOptions probe;
    for_each_leaf(probe, "", [&](const std::string&, auto&) { ++leaves; });
  }
  ASSERT_GT(leaves, 40u);
  std::size_t stored = 0;
  for (std::size_t k = 0; k < leaves; ++k) {
    ReconstructOptions changed;
    std::string name;
    std::size_t i = 0;
    for_each_leaf(changed, "", [&](const std::string& path, auto& value) {
      if (i++ == k) {
        name = path;
        change(value);
      }
    });
    bool expected = true;
    for (const std::string& n : not_stored)  // a name, or the fields of a struct ("closing.")
      if (n.back() == '.' ? name.rfind(n, 0) == 0 : name == n) expected = false;
    stored += expected;
    EXPECT_EQ(options_fingerprint(changed) != base, expected) << name;
  }
  EXPECT_GE(stored, 40u);
}
