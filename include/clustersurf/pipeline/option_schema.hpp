#pragma once
// The options of reconstruct() and mesh_tree() described once (core/option_spec.hpp): the CLI's
// flags and the Python module's keyword arguments, their help texts and defaults are made from
// this list, and the values either front end is given are checked here.

#include <clustersurf/core/option_spec.hpp>
#include <clustersurf/pipeline/reconstruct.hpp>

#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace clustersurf {

/// An option of reconstruct() or mesh_tree().
using OptionSpec = OptionSpecOf<ReconstructOptions>;

/// The options of reconstruct() (stage Build) and of mesh_tree() (stage Mesh), in the order the
/// front ends list them.
std::vector<OptionSpec> reconstruct_option_schema();

/// set_options() over reconstruct_option_schema(): the options of `stages` that `values` names.
void set_options(ReconstructOptions& o, const OptionValues& values,
                 std::vector<OptionStage> stages = {OptionStage::Build, OptionStage::Mesh});

}  // namespace clustersurf
