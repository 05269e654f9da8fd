#pragma once
// The recursion that builds a cluster tree's nodes (tree_builder.cpp).

#include "cluster/build_state.hpp"
#include "cluster/cluster_frame.hpp"
#include "cluster/support_fit.hpp"
#include "core/progress_reporter.hpp"

namespace clustersurf::detail {

/// Builds the tree of `work`'s points (all of work.local) into `root`, subtrees in parallel:
/// each node fitted, tried as a crease, split while its error or its support's misfit exceeds
/// the threshold (`tolerance` and `noise` in input units), each leaf's support fitted. `normals`:
/// the input normals indexed like the input (or null); `support` null skips the support checks;
/// `bias_tests` also splits a would-be leaf whose halves, each fitted with its own quadratic,
/// fit significantly better than its one against the noise (for noise that is the points' own,
/// kNoiseCountsShare of the spacing or more); `detail_splits` lets leaves at min_points split
/// below it where that resolves relief finer than them. With `field`, each cluster keeps the
/// noise where it lies: `noise` times its centroid's field value over `sigma` (the estimate the
/// field scales), between 1 and kMaxLocalNoise. The same tree for any thread count.
void build_nodes(BuildNode& root, const Points* normals, const FrameNormals& frame_normals, WorkingSet& work,
                 const SupportFit* support, const BuildOptions& options, double tolerance, double noise,
                 bool bias_tests, bool detail_splits, ProgressReporter& progress, const NoiseField* field = nullptr,
                 double sigma = 0);

}  // namespace clustersurf::detail
