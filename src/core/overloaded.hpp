#pragma once
// The "overloaded lambdas" helper for std::visit over the proxy variant.

namespace clustersurf::detail {

/// A visitor made of several lambdas: std::visit(Overloaded{[](A&){...}, [](B&){...}}, v).
template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

}  // namespace clustersurf::detail
