// The simple pendulum's closed form (equations in
// include/rigidae/exact/particle_pendulum.hpp).
#include "rigidae/exact/particle_pendulum.hpp"

#include <cmath>

#include <fmt/format.h>

#include "rigidae/exact/jacobi_elliptic.hpp"
#include "rigidae/model/joint_type.hpp"

namespace rigidae::exact {

namespace {

std::optional<ParticlePendulum> none(std::string* why, const std::string& text) {
  if (why != nullptr) *why = text;
  return std::nullopt;
}

}  // namespace

std::optional<ParticlePendulum> ParticlePendulum::of(const Scene& scene, std::string* why) {
  if (!scene.multibody) return none(why, "not a mechanism");
  const MultibodySpec& mb = *scene.multibody;
  const std::string general =
      "not the simple pendulum (one particle on a distance joint to a ground point, under gravity alone)";
  if (mb.bodies.size() != 1 || mb.joints.size() != 1 || !mb.bodies[0].particle || mb.joints[0].type == nullptr ||
      mb.joints[0].type->name != "distance" || !mb.springs.empty() || !mb.loads.empty() || !mb.drivers.empty())
    return none(why, general);
  const BodySpec& b = mb.bodies[0];
  const JointSpec& j = mb.joints[0];
  if (j.body_a != kGround && j.body_b != kGround) return none(why, general);
  // The rod's ground end, less the particle's own point (a particle does not
  // turn: its centre stays that offset from the rod's end).
  const Vec3 anchor = j.body_a == kGround ? Vec3(j.point_a - j.point_b) : Vec3(j.point_b - j.point_a);
  const double g = mb.gravity_W.norm();
  if (!(g > 0.0)) return none(why, "a particle pendulum without gravity (it moves uniformly on its sphere)");
  if (b.v0_W.norm() != 0.0)
    return none(why, "a particle pendulum started in motion (the closed form here is the release from rest)");
  ParticlePendulum p;
  p.body_ = b.name;
  p.anchor_ = anchor;
  p.L_ = j.length;
  p.down_ = mb.gravity_W / g;
  const Vec3 r = b.x0_W - anchor;
  const Vec3 horizontal = r - r.dot(p.down_) * p.down_;
  // theta0 from the downward vertical, in [0, pi].
  p.theta0_ = std::atan2(horizontal.norm(), r.dot(p.down_));
  if (!(p.theta0_ > 0.0) || !(p.theta0_ < M_PI) || horizontal.norm() < 1e-12 * p.L_)
    return none(why, "a particle pendulum released on the vertical (at rest at the bottom or at the top: no swing)");
  p.across_ = horizontal.normalized();
  p.k_ = std::sin(0.5 * p.theta0_);
  p.m_ = p.k_ * p.k_;
  p.m1_ = std::cos(0.5 * p.theta0_) * std::cos(0.5 * p.theta0_);
  p.K_ = complete_elliptic_k(p.m1_);
  p.w0_ = std::sqrt(g / p.L_);
  p.t0_ = scene.time.start;
  p.period_ = 4.0 * p.K_ / p.w0_;
  // The phase's rounding, 1e-16 |u| at the end, moves the bob by that times
  // its largest speed scale L w0 (per unit u: L).
  const double u_end = p.K_ + p.w0_ * std::abs(scene.time.end - scene.time.start);
  p.accuracy_ = 4.0 * 1e-16 * u_end * p.L_ + 1e-15 * p.L_;
  return p;
}

Vec3 ParticlePendulum::position(double t) const {
  const SnCnDn f = jacobi_sn_cn_dn(K_ - w0_ * (t - t0_), m_, m1_);
  const double sin_theta = 2.0 * k_ * f.sn * f.dn, cos_theta = 1.0 - 2.0 * m_ * f.sn * f.sn;
  return anchor_ + L_ * (sin_theta * across_ + cos_theta * down_);
}

std::string ParticlePendulum::name() const {
  return fmt::format("simple pendulum (Jacobi elliptic), amplitude {:.6g} rad, period {:.10g} s", theta0_, period_);
}

}  // namespace rigidae::exact
