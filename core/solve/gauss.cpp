#include "core/solve/gauss.h"

#include <cmath>
#include <stdexcept>

namespace ff {

GaussRule gauss_legendre(int n) {
  if (n < 1) throw std::invalid_argument("gauss_legendre: need at least one point");
  GaussRule rule;
  rule.points.resize(n);
  rule.weights.resize(n);
  for (int i = 0; i < n; ++i) {
    // Chebyshev-like initial guess, then Newton on P_n
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    rule.points[i] = -x;
    rule.weights[i] = 2.0 / ((1.0 - x * x) * dp * dp);
  }
  return rule;
}

}  // namespace ff
