#pragma once
// Rotation at constant body angular velocity: R(t) = R0 exp((t - t0) hat(omega)).
//
// The exact motion whenever omega stays along a principal axis and no torque
// turns it: a free body spinning about a principal axis (or any spherical
// body), a top spinning about its vertical symmetry axis.
#include <limits>
#include <string>
#include <utility>

#include "rigidae/exact/exact_solution.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::exact {

class SteadyRotation final : public ExactSolution {
 public:
  SteadyRotation(const Mat3& R0_WB, const Vec3& omega_B, double t0, double span, std::string name)
      : R0_(R0_WB), omega_(omega_B), t0_(t0), name_(std::move(name)) {
    // Rodrigues' formula is exact to round-off; the angle grows as |omega| t.
    accuracy_ = 1e-15 + 4.0 * std::numeric_limits<double>::epsilon() * omega_.norm() * span;
  }
  std::string name() const override { return name_; }
  RotationState at(double t) const override {
    const double rate = omega_.norm();
    if (rate == 0.0) return {R0_, omega_};
    return {R0_ * so3::axis_angle_to_matrix(omega_ / rate, rate * (t - t0_)), omega_};
  }
  double accuracy() const override { return accuracy_; }

 private:
  Mat3 R0_;
  Vec3 omega_;
  double t0_;
  std::string name_;
  double accuracy_;
};

}  // namespace rigidae::exact
