#pragma once
/// Gauss–Legendre rules on [-1, 1].
#include <vector>

namespace ff {

struct GaussRule {
  std::vector<double> points;   ///< abscissae in [-1, 1]
  std::vector<double> weights;  ///< weights summing to 2
};

/// n-point Gauss–Legendre rule (n >= 1), exact for polynomials of degree 2n-1.
/// Computed by Newton on the Legendre recurrence to machine precision.
GaussRule gauss_legendre(int n);

}  // namespace ff
