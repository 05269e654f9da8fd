#pragma once
// The fields of the option structs, named once: each option struct has a for_each_field(options,
// f) next to it that calls f(name, field) for every field in declaration order, and
// field_count<T>() counts an aggregate's fields, so a test can hold each list complete. What
// must see every option (the resume fingerprint of a tiled run) walks them instead of naming
// fields again.

#include <concepts>
#include <cstddef>
#include <optional>
#include <type_traits>

namespace clustersurf {

namespace detail {
/// Converts to any field type: T{AnyField{}, ...} compiles for at most as many as T has fields.
struct AnyField {
  template <class T>
  operator T() const;
};
}  // namespace detail

/// The number of fields of the aggregate T (no base classes).
template <class T, class... Fields>
consteval std::size_t field_count() {
  if constexpr (requires { T{Fields{}..., detail::AnyField{}}; })
    return field_count<T, Fields..., detail::AnyField>();
  else
    return sizeof...(Fields);
}

/// Whether T is a std::optional (an option that may be unset).
template <class T>
inline constexpr bool kIsOptional = false;
template <class T>
inline constexpr bool kIsOptional<std::optional<T>> = true;

/// `Options` is the struct T, const or not (the constraint of each for_each_field()).
template <class Options, class T>
concept OptionsOf = std::same_as<std::remove_const_t<Options>, T>;

}  // namespace clustersurf
