// The option words, parsed once in the library for the CLI and Python alike: each round-trips
// its to_string(), and each refusal names the option, what it accepts and what it got.

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/mesh/mesh_extraction.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>

#include <gtest/gtest.h>

#include <functional>

using namespace clustersurf;

namespace {

void expect_refused(const std::function<void()>& parse, const std::string& message) {
  try {
    parse();
    ADD_FAILURE() << "accepted; expected: " << message;
  } catch (const OptionError& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

}  // namespace

TEST(OptionText, EnumsRoundTripTheirNames) {
  for (ProxyKind k : {ProxyKind::Plane, ProxyKind::Poly, ProxyKind::Quadric})
    EXPECT_EQ(parse_proxy_kind(to_string(k)), k);
  for (SplitterKind k : {SplitterKind::SplitPlane, SplitterKind::Lloyd}) EXPECT_EQ(parse_splitter(to_string(k)), k);
  for (ErrorMetric m : {ErrorMetric::Rms, ErrorMetric::Max}) EXPECT_EQ(parse_error_metric(to_string(m)), m);
  for (MeshColoring c : {MeshColoring::None, MeshColoring::ByNode, MeshColoring::ByDistance, MeshColoring::FromInput,
                         MeshColoring::FromIntensity})
    EXPECT_EQ(parse_mesh_coloring(to_string(c)), c);
}

TEST(OptionText, RefusalsSayWhatIsAccepted) {
  expect_refused([] { parse_proxy_kind("point"); }, "proxy must be plane, poly or quadric, not \"point\"");
  expect_refused([] { parse_splitter("kmeans"); }, "splitter must be split-plane or lloyd, not \"kmeans\"");
  expect_refused([] { parse_error_metric("mean"); }, "error metric must be rms or max, not \"mean\"");
  expect_refused([] { parse_mesh_coloring("red"); },
                 "color must be none, leaf, distance, input or intensity, not \"red\"");
}

TEST(OptionText, LevelOfDetailFractionIsOfTheDiagonal) {
  ClusterTree tree;
  tree.bbox.extend(Eigen::Vector3d(0, 0, 0));
  tree.bbox.extend(Eigen::Vector3d(3, 4, 0));  // diagonal 5
  const LevelOfDetail lod = level_of_detail(tree, 4u, 0.01);
  EXPECT_EQ(lod.max_depth, 4u);
  EXPECT_DOUBLE_EQ(*lod.error_limit, 0.05);
  expect_refused([&] { level_of_detail(tree, std::nullopt, -0.1); },
                 "the level-of-detail error must be a non-negative fraction of the diagonal");
}
