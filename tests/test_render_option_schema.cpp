// The render option schema against RenderOptions: its defaults are the struct's, each option
// sets what it names and reads back what it set, and a refusal names the option.

#include "option_test_values.hpp"

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/render_option_schema.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

using namespace clustersurf;
using clustersurf::test::other_value;

namespace {

/// Every option's value in `o`, as the schema reads it.
std::vector<std::string> schema_values(const RenderOptions& o) {
  std::vector<std::string> out;
  for (const RenderOptionSpec& spec : render_option_schema()) out.push_back(spec.name + "=" + spec.get(o));
  return out;
}

std::string refusal(const OptionValues& values) {
  RenderOptions o;
  return test::refusal_of([&] { set_options(o, values); });
}

}  // namespace

TEST(RenderOptionSchema, DefaultsAreTheStructs) {
  const RenderOptions defaults;
  const CameraOptions camera;
  for (const RenderOptionSpec& spec : render_option_schema()) {
    const std::string text = default_text(spec);
    EXPECT_EQ(text.empty(), spec.optional) << spec.name;
    EXPECT_EQ(spec.stage, OptionStage::Render) << spec.name;
    if (text.empty()) continue;
    RenderOptions o;
    spec.set(o, text);
    EXPECT_EQ(schema_values(o), schema_values(defaults)) << spec.name << " = " << text;
  }
  RenderOptions o;
  set_options(o, {{"width", std::to_string(defaults.width)}, {"fov", number_text(camera.fov)}});
  EXPECT_EQ(o.width, defaults.width);
  EXPECT_EQ(o.camera.fov, camera.fov);
  EXPECT_EQ(o.background, defaults.background);
}

TEST(RenderOptionSchema, EachOptionSetsWhatItNamesAndReadsItBack) {
  const std::vector<std::string> defaults = schema_values(RenderOptions{});
  std::set<std::string> names;
  for (const RenderOptionSpec& spec : render_option_schema()) {
    EXPECT_TRUE(names.insert(spec.name).second) << spec.name;
    EXPECT_FALSE(spec.help.empty()) << spec.name;
    const std::string text = other_value(spec);
    RenderOptions o;
    set_options(o, {{spec.name, text}});
    EXPECT_EQ(spec.get(o), text) << spec.name;
    const std::vector<std::string> after = schema_values(o);
    std::size_t changed = 0;
    for (std::size_t k = 0; k < after.size(); ++k) changed += after[k] != defaults[k];
    EXPECT_EQ(changed, 1u) << spec.name << " = " << text;
  }
  RenderOptions o;
  set_options(o, {{"eye", "1,-2,3.5"}, {"background", "#ff8000"}, {"ao", "true"}, {"show", "error"}});
  ASSERT_TRUE(o.camera.eye.has_value());
  EXPECT_EQ(*o.camera.eye, Eigen::Vector3d(1, -2, 3.5));
  EXPECT_EQ(o.background, (Rgba8{255, 128, 0, 255}));
  EXPECT_TRUE(o.ambient_occlusion);
  EXPECT_EQ(o.show, ShowMode::Error);
}

TEST(RenderOptionSchema, RefusalsNameTheOption) {
  EXPECT_EQ(refusal({{"width", "0"}}), "width must be a whole number from 1 to 32768, not \"0\"");
  EXPECT_EQ(refusal({{"samples", "2000"}}), "samples must be a whole number from 1 to 1024, not \"2000\"");
  EXPECT_EQ(refusal({{"elevation", "90"}}), "elevation must be a number from -89.9 to 89.9, not \"90\"");
  EXPECT_EQ(refusal({{"fov", "nan"}}), "fov must be a number from 1 to 170, not \"nan\"");
  EXPECT_EQ(refusal({{"distance", "0"}}), "distance must be a positive number, not \"0\"");
  EXPECT_EQ(refusal({{"show", "edges"}}), "show must be surface, clusters, spheres, proxies or error, not \"edges\"");
  EXPECT_EQ(refusal({{"background", "pink"}}), "background must be transparent, white, black or #rrggbb, not \"pink\"");
  EXPECT_EQ(refusal({{"highlight", "-1"}}).substr(0, 34), "highlight must be a whole number f");
  for (const std::string bad : {"1,2", "1,2,3,4", "1,,3", "a,b,c", "1,2,inf", ""})
    EXPECT_EQ(refusal({{"eye", bad}}), "eye must be three numbers x,y,z, not \"" + bad + "\"");
  EXPECT_EQ(refusal({{"resolution", "64"}}), "unknown option \"resolution\"");
  EXPECT_EQ(refusal({{"ao", "true"}, {"ao", "false"}}), "option ao is given twice");
}
