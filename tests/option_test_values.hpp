#pragma once
// What the option schemas' tests share: a value each option takes other than its default, and
// the message a refused setting gives.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/core/option_spec.hpp>

#include <algorithm>
#include <string>

namespace clustersurf::test {

/// A value the option takes other than its default.
template <class Options>
std::string other_value(const OptionSpecOf<Options>& spec) {
  const std::string d = default_text(spec);
  switch (spec.kind) {
    case OptionKind::Flag:
      return d == "true" ? "false" : "true";
    case OptionKind::Word:
      return *std::find_if(spec.words.begin(), spec.words.end(), [&](const std::string& w) { return w != d; });
    case OptionKind::Whole:
      return d.empty() || d == "auto" ? "7" : std::to_string(std::stoull(d) + 1);
    case OptionKind::Number:
      return d.empty() || d == "auto" ? "0.25" : number_text(std::stod(d) * 2 + 0.5);
    case OptionKind::Vector:
      return "1,2,3";
  }
  return d;
}

/// The OptionError message of `set()`, or "accepted".
template <class Set>
std::string refusal_of(Set&& set) {
  try {
    set();
  } catch (const OptionError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace clustersurf::test
