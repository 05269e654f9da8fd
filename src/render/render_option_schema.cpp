// The render options described once: what the CLI's `render` and Python's Tree.render() take.

#include <clustersurf/render/render_option_schema.hpp>

#include "core/option_builders.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace clustersurf {

namespace {

using Spec = RenderOptionSpec;
using detail::unset_by_default;
using detail::with_words;

Spec spec(std::string name, OptionKind kind, std::string help, std::function<std::string(const RenderOptions&)> get,
          std::function<void(RenderOptions&, std::string_view)> set) {
  return detail::spec<RenderOptions>(std::move(name), OptionStage::Render, kind, std::move(help), std::move(get),
                                     std::move(set));
}

/// An int field from `low` to `high`.
Spec whole(std::string name, std::string help, int RenderOptions::*member, int low, int high) {
  return spec(
      name, OptionKind::Whole, std::move(help), [member](const RenderOptions& o) { return std::to_string(o.*member); },
      [member, name, low, high](RenderOptions& o, std::string_view text) {
        o.*member = static_cast<int>(
            parse_whole(name, text, static_cast<std::uint64_t>(low), static_cast<std::uint64_t>(high)));
      });
}

/// A real field, given by `field`, within `bound` or from `low` to `high` when they are given.
template <class Field>
Spec real(std::string name, std::string help, Field field, RealBound bound, double low = 0, double high = 0) {
  return spec(
      name, OptionKind::Number, std::move(help), [field](const RenderOptions& o) { return number_text(field(o)); },
      [field, name, bound, low, high](RenderOptions& o, std::string_view text) {
        field(o) = low < high ? parse_real_in(name, text, low, high) : parse_real(name, text, bound);
      });
}

/// An optional field, given by `field`, unset by default; `parse` reads its text.
template <class Field, class Parse>
Spec optional(std::string name, OptionKind kind, std::string help, Field field, Parse parse) {
  return unset_by_default(spec(
      name, kind, std::move(help),
      [field](const RenderOptions& o) {
        const auto& v = field(o);
        if (!v) return std::string();
        if constexpr (std::is_same_v<std::decay_t<decltype(*v)>, Eigen::Vector3d>)
          return vector_text((*v)(0), (*v)(1), (*v)(2));
        else if constexpr (std::is_floating_point_v<std::decay_t<decltype(*v)>>)
          return number_text(*v);
        else
          return std::to_string(*v);
      },
      [field, parse, name](RenderOptions& o, std::string_view text) { field(o) = parse(name, text); }));
}

/// An optional camera vector x,y,z.
template <class Field>
Spec vector(std::string name, std::string help, Field field) {
  return optional(name, OptionKind::Vector, std::move(help), field, [](const std::string& n, std::string_view text) {
    const std::array<double, 3> v = parse_vector(n, text);
    return Eigen::Vector3d(v[0], v[1], v[2]);
  });
}

std::vector<Spec> picture_options() {
  std::vector<Spec> out;
  out.push_back(whole("width", "Picture width in pixels", &RenderOptions::width, 1, 32768));
  out.push_back(whole("height", "Picture height in pixels", &RenderOptions::height, 1, 32768));
  out.push_back(whole("samples", "Rays per pixel (anti-aliasing)", &RenderOptions::samples, 1, 1024));
  out.push_back(detail::word_spec<RenderOptions>(
      "mode", OptionStage::Render, {"implicit", "hit-blend", "brute-force"},
      "Intersection: implicit (first zero of f), hit-blend (blend the proxies' hits, thesis 5.1) or brute-force "
      "(implicit without the hierarchy)",
      [](auto& o) -> auto& { return o.mode; }, parse_intersect_mode));
  out.push_back(detail::word_spec<RenderOptions>(
      "show", OptionStage::Render, {"surface", "clusters", "spheres", "proxies", "error"},
      "What to draw: surface, clusters, spheres, proxies or error (the distance to the input points, which it needs)",
      [](auto& o) -> auto& { return o.show; }, parse_show_mode));
  out.push_back(optional(
      "level", OptionKind::Whole, "clusters: color by the ancestor at this depth instead of the leaf",
      [](auto& o) -> auto& { return o.level; },
      [](const std::string& n, std::string_view text) {
        return static_cast<std::uint32_t>(parse_whole(n, text, 0, std::numeric_limits<std::uint32_t>::max()));
      }));
  out.push_back(optional(
      "highlight", OptionKind::Whole, "Draw this node's cluster and proxy in red over the grey surface",
      [](auto& o) -> auto& { return o.highlight; },
      [](const std::string& n, std::string_view text) {
        return static_cast<std::int32_t>(parse_whole(n, text, 0, std::numeric_limits<std::int32_t>::max()));
      }));
  out.push_back(optional(
      "error_scale", OptionKind::Number, "error: distance drawn full red (default 0.005 x diagonal)",
      [](auto& o) -> auto& { return o.error_scale; },
      [](const std::string& n, std::string_view text) { return parse_real(n, text, RealBound::Positive); }));
  return out;
}

std::vector<Spec> camera_options() {
  std::vector<Spec> out;
  out.push_back(real(
      "azimuth", "Camera turn around the up axis, degrees", [](auto& o) -> auto& { return o.camera.azimuth; },
      RealBound::Any));
  out.push_back(real(
      "elevation", "Camera elevation, degrees", [](auto& o) -> auto& { return o.camera.elevation; }, RealBound::Any,
      -89.9, 89.9));
  out.push_back(optional(
      "distance", OptionKind::Number, "Camera distance to the target (default: the model fills the view)",
      [](auto& o) -> auto& { return o.camera.distance; },
      [](const std::string& n, std::string_view text) { return parse_real(n, text, RealBound::Positive); }));
  out.push_back(real(
      "fov", "Vertical field of view, degrees", [](auto& o) -> auto& { return o.camera.fov; }, RealBound::Any, 1, 170));
  out.push_back(vector(
      "eye", "Explicit camera position x,y,z", [](auto& o) -> auto& { return o.camera.eye; }));
  out.push_back(vector(
      "target", "Point looked at x,y,z (default: bbox center)", [](auto& o) -> auto& { return o.camera.target; }));
  out.push_back(vector(
      "up",
      "Up direction x,y,z (default: the input's up axis: 0,0,1 for LAS, E57 and PTX surveys and what "
      "was made from them, else 0,1,0)",
      [](auto& o) -> auto& { return o.camera.up; }));
  return out;
}

std::vector<Spec> shading_options() {
  std::vector<Spec> out;
  out.push_back(with_words(
      spec(
          "background", OptionKind::Word, "transparent, white, black or #rrggbb",
          [](const RenderOptions& o) { return background_text(o.background); },
          [](RenderOptions& o, std::string_view text) { o.background = parse_background(std::string(text)); }),
      {"transparent", "white", "black", "#rrggbb"}));
  out.push_back(detail::flag_spec<RenderOptions>(
      "ao", OptionStage::Render, "Ambient occlusion (8 short rays per hit)",
      [](auto& o) -> auto& { return o.ambient_occlusion; }));
  out.push_back(real(
      "min_weight", "Surface only where the total weight exceeds this (as the mesher)",
      [](auto& o) -> auto& { return o.min_weight; }, RealBound::NonNegative));
  out.push_back(real(
      "point_radius", "Point clouds: splat radius (0: 0.75 x mean spacing)",
      [](auto& o) -> auto& { return o.point_radius; }, RealBound::NonNegative));
  return out;
}

}  // namespace

std::vector<RenderOptionSpec> render_option_schema() {
  std::vector<Spec> out = picture_options();
  for (auto* part : {&camera_options, &shading_options})
    for (Spec& s : part()) out.push_back(std::move(s));
  return out;
}

void set_options(RenderOptions& o, const OptionValues& values) {
  set_options(o, render_option_schema(), values, {OptionStage::Render});
}

std::string background_text(const Rgba8& color) {
  if (color.a == 0) return "transparent";
  if (color.r == 255 && color.g == 255 && color.b == 255) return "white";
  if (color.r == 0 && color.g == 0 && color.b == 0) return "black";
  return fmt::format("#{:02x}{:02x}{:02x}", color.r, color.g, color.b);
}

}  // namespace clustersurf
