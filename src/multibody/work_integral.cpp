// The work of a power sampled at the accepted steps (see work_integral.hpp).
#include "rigidae/multibody/work_integral.hpp"

#include <algorithm>

namespace rigidae::multibody {

void WorkIntegral::add(double t, double P) {
  if (count_ == kPoints) {
    std::copy(t_ + 1, t_ + kPoints, t_);
    std::copy(p_ + 1, p_ + kPoints, p_);
    --count_;
  }
  t_[count_] = t;
  p_[count_] = P;
  ++count_;
  if (count_ < 2) return;
  const int n = count_;
  const double a = t_[n - 2], b = t_[n - 1];
  if (!(b > a)) return;
  // Gauss-Legendre nodes and weights on [-1, 1], 4 points.
  static constexpr double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  static constexpr double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
  double integral = 0.0;
  for (int g = 0; g < 4; ++g) {
    const double tg = 0.5 * (a + b) + 0.5 * (b - a) * x[g];
    double p = 0.0;  // Lagrange form of the interpolating polynomial
    for (int i = 0; i < n; ++i) {
      double l = 1.0;
      for (int k = 0; k < n; ++k)
        if (k != i) l *= (tg - t_[k]) / (t_[i] - t_[k]);
      p += l * p_[i];
    }
    integral += w[g] * p;
  }
  work_ += 0.5 * (b - a) * integral;
}

}  // namespace rigidae::multibody
