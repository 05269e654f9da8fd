#pragma once
// The options of reconstruct() and mesh_tree() described once: name, kind, help, the words they
// take, and how each reads from and writes to ReconstructOptions. The CLI's flags, the Python
// module's keyword arguments, their help texts and their defaults are all made from this list,
// and the values either front end is given are checked here, with messages naming the option.

#include <clustersurf/pipeline/reconstruct.hpp>

#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace clustersurf {

/// Which stage an option configures: the tree's build or the mesh of its surface.
enum class OptionStage : std::uint8_t { Build, Mesh };

/// The kind of value an option takes, as the front ends present it.
enum class OptionKind : std::uint8_t {
  Flag,    ///< on or off; "true" or "false" as text
  Whole,   ///< a whole number (or one of `words`)
  Number,  ///< a real number (or one of `words`)
  Word,    ///< one of `words`
};

/// One option, described once for every front end.
struct OptionSpec {
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
  std::function<std::string(const ReconstructOptions& o)> get;
  /// Sets the option in `o` from text. Throws OptionError naming the option when the text is not
  /// a value it takes.
  std::function<void(ReconstructOptions& o, std::string_view text)> set;
};

/// The options of reconstruct() (stage Build) and of mesh_tree() (stage Mesh), in the order the
/// front ends list them.
std::vector<OptionSpec> reconstruct_option_schema();

/// get() of the default ReconstructOptions: the option's documented default.
std::string default_text(const OptionSpec& spec);

/// Option values by name (or alias), as text, in any order.
using OptionValues = std::vector<std::pair<std::string, std::string>>;

/// Sets the options `values` names in `o`, in the schema's order whatever the order given (an
/// absolute tolerance overrides a relative one). Only options of `stages` are taken. Throws
/// OptionError for a name the schema does not have in those stages, for an option given twice
/// (by its name and its alias) and for a value the option does not take.
void set_options(ReconstructOptions& o, const OptionValues& values,
                 std::vector<OptionStage> stages = {OptionStage::Build, OptionStage::Mesh});

/// A number as the schema writes it: the shortest text that reads back as the same double.
std::string number_text(double value);

}  // namespace clustersurf
