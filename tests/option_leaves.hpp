#pragma once
// The option structs' plain fields, walked through the nested ones (for_each_field()), for the
// tests that hold the field lists, the fingerprint and the option schema complete.

#include <clustersurf/core/option_fields.hpp>

#include <sstream>
#include <string>
#include <type_traits>

namespace clustersurf::test {

/// Calls f(path, field) for every field that is no option struct, through the nested ones.
template <class Options, class F>
void for_each_leaf(Options& o, const std::string& prefix, F&& f) {
  for_each_field(o, [&](std::string_view name, auto& value) {
    using V = std::remove_cvref_t<decltype(value)>;
    // Appended rather than concatenated: GCC 12 at -O3 takes `prefix + name` here for an
    // overflowing copy (-Wstringop-overflow, a false positive of the same family as bug 105329).
    std::string path = prefix;
    path.append(name);
    if constexpr (std::is_arithmetic_v<V> || std::is_enum_v<V> || kIsOptional<V>)
      f(path, value);
    else
      for_each_leaf(value, path + ".", f);
  });
}

/// Every plain field of `o` as "path=value" lines, exact (17 digits).
template <class Options>
std::string leaf_values(const Options& o) {
  std::ostringstream out;
  out.precision(17);
  for_each_leaf(o, "", [&](const std::string& path, const auto& value) {
    using V = std::remove_cvref_t<decltype(value)>;
    out << path << '=';
    if constexpr (kIsOptional<V>) {
      if (value)
        out << +*value;
      else
        out << "unset";
    } else if constexpr (std::is_enum_v<V>) {
      out << static_cast<long long>(value);
    } else {
      out << +value;
    }
    out << '\n';
  });
  return out.str();
}

}  // namespace clustersurf::test
