// The option schema against the option structs: its defaults are the structs', each option
// sets the field it names and reads back what it set, every field a user may set is in it,
// and a refusal names the option.

#include "option_leaves.hpp"
#include "option_test_values.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/pipeline/option_schema.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <string>

using namespace clustersurf;
using clustersurf::test::for_each_leaf;
using clustersurf::test::leaf_values;
using clustersurf::test::other_value;

namespace {

/// Fields the front ends do not set: whether to mesh (they ask for a mesh file or call a mesh
/// function), the method's tuned rules and the machine's limits, set only through the API.
const std::set<std::string> kApiOnly = {"mesh",
                                        "build.frames_from_normals",
                                        "build.fit_normals",
                                        "build.outliers.neighbors",
                                        "build.outliers.local_ratio",
                                        "build.outliers.global_ratio",
                                        "build.outliers.plane_neighbors",
                                        "build.outliers.min_points",
                                        "build.noise.neighbors",
                                        "build.noise.samples",
                                        "build.noise.min_width_ratio",
                                        "build.noise.detail_ratio",
                                        "build.noise.noisy_width_ratio",
                                        "build.noise.residual_differences",
                                        "build.noise.facing_normals",
                                        "build.noise.local",
                                        "meshing.grid.newton_steps",
                                        "meshing.grid.min_weight",
                                        "meshing.grid.fill_cells",
                                        "meshing.grid.fill_cell",
                                        "meshing.grid.memory_limit",
                                        "meshing.trim.neighbors",
                                        "meshing.refit.rings",
                                        "meshing.closing.resolution",
                                        "meshing.decimation.lock_boundary",
                                        "meshing.trim.typical_spread",
                                        "meshing.distance_scale"};

bool api_only(const std::string& path) { return kApiOnly.contains(path); }

/// The plain fields whose values differ between `a` and `b`.
std::set<std::string> changed_fields(const ReconstructOptions& a, const ReconstructOptions& b) {
  std::map<std::string, std::string> before;
  std::istringstream lines(leaf_values(a));
  for (std::string line; std::getline(lines, line);) before[line.substr(0, line.find('='))] = line;
  std::set<std::string> out;
  std::istringstream after(leaf_values(b));
  for (std::string line; std::getline(after, line);)
    if (before[line.substr(0, line.find('='))] != line) out.insert(line.substr(0, line.find('=')));
  return out;
}

std::string refusal(const OptionValues& values,
                    std::vector<OptionStage> stages = {OptionStage::Build, OptionStage::Mesh}) {
  ReconstructOptions o;
  return test::refusal_of([&] { set_options(o, values, std::move(stages)); });
}

}  // namespace

TEST(OptionSchema, DefaultsAreTheStructs) {
  const ReconstructOptions defaults;
  for (const OptionSpec& spec : reconstruct_option_schema()) {
    const std::string text = default_text(spec);
    EXPECT_EQ(text.empty(), spec.optional) << spec.name;
    if (text.empty()) continue;
    ReconstructOptions o;
    spec.set(o, text);
    EXPECT_EQ(leaf_values(o), leaf_values(defaults)) << spec.name << " = " << text;
  }
}

TEST(OptionSchema, EachOptionSetsItsFieldAndReadsItBack) {
  const ReconstructOptions defaults;
  std::set<std::string> reached;
  for (const OptionSpec& spec : reconstruct_option_schema()) {
    const std::string text = other_value(spec);
    ReconstructOptions o;
    set_options(o, {{spec.name, text}});
    EXPECT_EQ(spec.get(o), text) << spec.name;
    const std::set<std::string> changed = changed_fields(defaults, o);
    EXPECT_FALSE(changed.empty()) << spec.name << " = " << text << " changed no field";
    for (const std::string& path : changed) {
      EXPECT_EQ(path.starts_with("meshing."), spec.stage == OptionStage::Mesh) << spec.name << " sets " << path;
      reached.insert(path);
    }
  }
  ReconstructOptions probe;
  for_each_leaf(probe, "", [&](const std::string& path, auto&) {
    EXPECT_TRUE(reached.contains(path) || api_only(path)) << path << " is neither in the schema nor API-only";
    EXPECT_FALSE(reached.contains(path) && api_only(path)) << path << " is in the schema and listed API-only";
  });
}

TEST(OptionSchema, NamesAreUniqueAndTheCliWords) {
  std::set<std::string> names;
  for (const OptionSpec& spec : reconstruct_option_schema()) {
    EXPECT_TRUE(names.insert(spec.name).second) << spec.name;
    if (!spec.alias.empty()) {
      EXPECT_TRUE(names.insert(spec.alias).second) << spec.alias;
    }
    EXPECT_EQ(spec.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_"), std::string::npos) << spec.name;
    EXPECT_FALSE(spec.help.empty()) << spec.name;
    EXPECT_EQ(spec.kind == OptionKind::Word, !spec.words.empty() && spec.words.front() != "auto") << spec.name;
  }
}

TEST(OptionSchema, RefusalsNameTheOption) {
  EXPECT_EQ(refusal({{"alpha", "-1"}}), "alpha must be \"auto\" or a positive number, not \"-1\"");
  EXPECT_EQ(refusal({{"alpha", "nan"}}), "alpha must be \"auto\" or a positive number, not \"nan\"");
  EXPECT_EQ(refusal({{"trim", "2x"}}), "trim must be a number >= 0, not \"2x\"");
  // A bound that only says what the type holds is left unsaid.
  EXPECT_EQ(refusal({{"decimate", "0.2"}}), "decimate must be a whole number >= 0, not \"0.2\"");
  EXPECT_EQ(refusal({{"proxy", "cubic"}}), "proxy must be plane, poly or quadric, not \"cubic\"");
  EXPECT_EQ(refusal({{"watertight", "yes"}}), "watertight must be true or false, not \"yes\"");
  EXPECT_EQ(refusal({{"smoothness", "1"}}), "unknown option \"smoothness\"");
  EXPECT_EQ(refusal({{"alpha", "1"}}, {OptionStage::Mesh}), "unknown option \"alpha\"");
  EXPECT_EQ(refusal({{"tolerance", "0.001"}, {"max_error", "0.002"}}),
            "give tolerance or its older name max_error, not both");
  EXPECT_EQ(refusal({{"seed", "1"}, {"seed", "2"}}), "option seed is given twice");
  for (const std::string bad : {"big", "-1", "1e", "", " 0.1", "nan", "inf"})
    EXPECT_EQ(refusal({{"tolerance", bad}}), "tolerance must be \"auto\" or a number >= 0, not \"" + bad + "\"");
  for (const std::string bad : {"0", "many", "-5", "2.5", "1073741825"})
    EXPECT_EQ(refusal({{"min_points", bad}}),
              "min_points must be \"auto\" or a whole number from 1 to 1073741824, not \"" + bad + "\"");
  for (const std::string bad : {"1", "fine", "100001", "64x"})
    EXPECT_EQ(refusal({{"resolution", bad}}),
              "resolution must be \"auto\" or a whole number from 2 to 100000, not \"" + bad + "\"");
}

TEST(OptionSchema, AnAbsoluteToleranceOverridesARelativeOneInAnyOrder) {
  for (const OptionValues& values : {OptionValues{{"tolerance", "0.01"}, {"absolute_error", "0.5"}},
                                     OptionValues{{"absolute_tolerance", "0.5"}, {"max_error", "0.01"}}}) {
    ReconstructOptions o;
    set_options(o, values);
    EXPECT_EQ(o.build.threshold_mode, ThresholdMode::Absolute);
    EXPECT_EQ(o.build.tolerance, 0.5);
  }
  ReconstructOptions o;
  set_options(o, {{"tolerance", "0.01"}});
  EXPECT_EQ(o.build.threshold_mode, ThresholdMode::Auto);
  EXPECT_EQ(o.build.tolerance, 0.01);
  set_options(o, {{"tolerance", "auto"}});
  EXPECT_EQ(o.build.tolerance, BuildOptions{}.tolerance);
}

TEST(OptionSchema, NumbersReadBackExactly) {
  for (const double x : {0.1, 1.0 / 3.0, 5e-05, 1e300, 0.75}) {
    ReconstructOptions o;
    set_options(o, {{"alpha", number_text(x)}});
    EXPECT_EQ(o.build.alpha, x);
  }
}
