#pragma once
// The simple pendulum in closed form, for a mechanism that is one: a single
// particle (kind = "particle") held by a distance joint to a ground point a
// at the rod length L, under gravity g alone (no springs, loads or drivers),
// released at rest at the angle theta0 in (0, pi) from the downward vertical
// (problems/particle_pendulum.toml). With k = sin(theta0 / 2), m = k^2,
// K = K(m), w0 = sqrt(|g| / L) and u = K - w0 (t - t0):
//   sin(theta / 2) = k sn(u | m),  so  sin(theta) = 2 k sn dn,  cos(theta) = 1 - 2 k^2 sn^2,
//   p(t) = a + L (sin(theta) e + cos(theta) d),
// d the unit vector along g and e the horizontal unit vector towards the
// start (the motion stays in their plane); period 4 K / w0. No small-angle
// approximation. A start in motion, at the bottom or at the top is not
// covered (`why` says which).
#include <optional>
#include <string>

#include "rigidae/core/types.hpp"
#include "rigidae/model/scene.hpp"

namespace rigidae::exact {

class ParticlePendulum {
 public:
  // The particle's position (m, space) at absolute scene time t (s).
  Vec3 position(double t) const;
  const std::string& body() const { return body_; }
  double period() const { return period_; }
  // "simple pendulum (Jacobi elliptic), amplitude ... rad"
  std::string name() const;
  // Position accuracy (m) over the span it was built for: the argument u's
  // rounding, ~1e-16 |u| in the phase, times the bob's speed scale.
  double accuracy() const { return accuracy_; }

  // The closed form of the scene's mechanism, or nullopt with `why` filled.
  static std::optional<ParticlePendulum> of(const Scene& scene, std::string* why);

 private:
  std::string body_;
  Vec3 anchor_ = Vec3::Zero(), down_ = Vec3::Zero(), across_ = Vec3::Zero();
  double L_ = 1.0, k_ = 0.0, m_ = 0.0, m1_ = 1.0, K_ = 0.0, w0_ = 0.0, t0_ = 0.0, theta0_ = 0.0;
  double period_ = 0.0, accuracy_ = 0.0;
};

}  // namespace rigidae::exact
