#pragma once
// An option described once for every front end: its name, kind, help, the words it takes, and
// how it reads from and writes to an option struct as text. The CLI's flags and the Python
// module's keywords, their help texts and defaults are made from such lists, and the values
// either front end is given are checked by set_options(), with messages naming the option.

#include <clustersurf/core/errors.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace clustersurf {

/// Which step an option configures: the tree's build, the mesh of its surface, or a picture.
enum class OptionStage : std::uint8_t { Build, Mesh, Render };

/// The kind of value an option takes, as the front ends present it.
enum class OptionKind : std::uint8_t {
  Flag,    ///< on or off; "true" or "false" as text
  Whole,   ///< a whole number (or one of `words`)
  Number,  ///< a real number (or one of `words`)
  Word,    ///< one of `words`
  Vector,  ///< three real numbers, "x,y,z" as text
};

/// One option of the struct `Options`, described once for every front end.
template <class Options>
struct OptionSpecOf {
  std::string name;   ///< snake_case: the Python keyword; the CLI flag is --kebab-case
  std::string alias;  ///< an older name taking the same value, or empty
  OptionStage stage = OptionStage::Build;
  OptionKind kind = OptionKind::Number;
  /// The words the option takes: its choices (Word), or what it takes besides a number ("auto").
  std::vector<std::string> words;
  /// Whether the option may be unset (its default is then no value: get() gives "").
  bool optional = false;
  std::string help;  ///< what the option does, without its default
  /// The option's value in `o` as text set() takes back; "" for an unset optional.
  std::function<std::string(const Options& o)> get;
  /// Sets the option in `o` from text. Throws OptionError naming the option when the text is not
  /// a value it takes.
  std::function<void(Options& o, std::string_view text)> set;
};

/// get() of the default options: the option's documented default ("" for an unset optional).
template <class Options>
std::string default_text(const OptionSpecOf<Options>& spec) {
  return spec.get(Options{});
}

/// Option values by name (or alias), as text, in any order.
using OptionValues = std::vector<std::pair<std::string, std::string>>;

/// Sets the options `values` names in `o`, in the schema's order whatever the order given (an
/// absolute tolerance overrides a relative one). Only options of `stages` are taken. Throws
/// OptionError for a name the schema does not have in those stages, for an option given twice
/// (by its name and its alias) and for a value the option does not take.
template <class Options>
void set_options(Options& o, const std::vector<OptionSpecOf<Options>>& schema, const OptionValues& values,
                 const std::vector<OptionStage>& stages) {
  std::vector<const std::pair<std::string, std::string>*> given(schema.size(), nullptr);
  for (const auto& value : values) {
    const std::string& name = value.first;
    const auto it = std::find_if(schema.begin(), schema.end(), [&](const OptionSpecOf<Options>& s) {
      return (s.name == name || (!s.alias.empty() && s.alias == name)) &&
             std::find(stages.begin(), stages.end(), s.stage) != stages.end();
    });
    if (it == schema.end()) throw OptionError("unknown option \"" + name + "\"");
    const auto i = static_cast<std::size_t>(it - schema.begin());
    if (given[i])
      throw OptionError(given[i]->first == name
                            ? "option " + name + " is given twice"
                            : "give " + it->name + " or its older name " + it->alias + ", not both");
    given[i] = &value;
  }
  for (std::size_t i = 0; i < schema.size(); ++i)
    if (given[i]) schema[i].set(o, given[i]->second);
}

/// A number as the schemas write it: the shortest text that reads back as the same double.
std::string number_text(double value);
/// Three numbers as a Vector option's text: "x,y,z", each as number_text().
std::string vector_text(double x, double y, double z);
/// `text` in double quotes, for messages.
std::string quoted(std::string_view text);
/// "a, b or c".
std::string word_list(const std::vector<std::string>& words);

/// A whole number from `low` to `high` as the whole text (or the word `word`, which the caller
/// handles); OptionError naming `name` otherwise.
std::uint64_t parse_whole(std::string_view name, std::string_view text, std::uint64_t low, std::uint64_t high,
                          std::string_view word = {});
/// A finite real number from `low` to `high` as the whole text; OptionError naming `name` otherwise.
double parse_real_in(std::string_view name, std::string_view text, double low, double high);
/// Which reals a parse_real() takes.
enum class RealBound : std::uint8_t { NonNegative, Positive, Any };
/// A finite real number within `bound` as the whole text (or the word `word`, which the caller
/// handles); OptionError naming `name` otherwise.
double parse_real(std::string_view name, std::string_view text, RealBound bound, std::string_view word = {});
/// "true" or "false"; OptionError naming `name` otherwise.
bool parse_flag(std::string_view name, std::string_view text);
/// Three finite reals "x,y,z"; OptionError naming `name` otherwise.
std::array<double, 3> parse_vector(std::string_view name, std::string_view text);

}  // namespace clustersurf
