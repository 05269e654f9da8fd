#pragma once
// Builders of the option schemas' entries (core/option_spec.hpp): an option from its getter and
// setter, with its words, an older name, unset by default; flags and words bound to a field.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/core/option_spec.hpp>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace clustersurf::detail {

template <class Options>
OptionSpecOf<Options> spec(std::string name, OptionStage stage, OptionKind kind, std::string help,
                           std::function<std::string(const Options&)> get,
                           std::function<void(Options&, std::string_view)> set) {
  OptionSpecOf<Options> s;
  s.name = std::move(name);
  s.stage = stage;
  s.kind = kind;
  s.help = std::move(help);
  s.get = std::move(get);
  s.set = std::move(set);
  return s;
}

template <class Options>
OptionSpecOf<Options> with_words(OptionSpecOf<Options> s, std::vector<std::string> words) {
  s.words = std::move(words);
  return s;
}

template <class Options>
OptionSpecOf<Options> with_alias(OptionSpecOf<Options> s, std::string alias) {
  s.alias = std::move(alias);
  return s;
}

template <class Options>
OptionSpecOf<Options> unset_by_default(OptionSpecOf<Options> s) {
  s.optional = true;
  return s;
}

/// A flag bound to the bool `field(o)`; `negated`: the flag turns the field off.
template <class Options, class Field>
OptionSpecOf<Options> flag_spec(std::string name, OptionStage stage, std::string help, Field field,
                                bool negated = false) {
  return spec<Options>(
      name, stage, OptionKind::Flag, std::move(help),
      [field, negated](const Options& o) { return std::string(field(o) != negated ? "true" : "false"); },
      [field, negated, name](Options& o, std::string_view text) { field(o) = parse_flag(name, text) != negated; });
}

/// A word from `words` bound to the enum `field(o)` through `parse` and to_string().
template <class Options, class Field, class Parse>
OptionSpecOf<Options> word_spec(std::string name, OptionStage stage, std::vector<std::string> words, std::string help,
                                Field field, Parse parse) {
  auto get = [field](const Options& o) { return std::string(to_string(field(o))); };
  auto set = [field, parse, n = name, words](Options& o, std::string_view text) {
    if (std::find(words.begin(), words.end(), text) == words.end())
      throw OptionError(n + " must be " + word_list(words) + ", not " + quoted(text));
    field(o) = parse(std::string(text));
  };
  return with_words(spec<Options>(std::move(name), stage, OptionKind::Word, std::move(help), get, set), words);
}

}  // namespace clustersurf::detail
