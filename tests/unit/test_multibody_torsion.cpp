// A revolute joint's torsional spring-damper against exact solutions: one
// body on a revolute joint to the ground at its centre of mass, no gravity,
// is a (damped) harmonic oscillator about the axis,
//   J theta'' + c theta' + k (theta - theta0) = 0,  J = z_B^T I z_B,
// theta(0) = 0, theta'(0) = w0, so with beta = c / 2J, Omega^2 = k / J,
// wd = sqrt(Omega^2 - beta^2):
//   theta - theta0 = exp(-beta t) (A cos(wd t) + B sin(wd t)),
//   A = -theta0, B = (w0 + beta A) / wd,
// and the body's orientation is the rotation by theta about the space axis
// applied to the initial one. The body's inertia is a full tensor and the
// axis is not principal, so the joint's other rows carry reactions.
// Exact iteration matrices with torsion: test_multibody_jacobians.cpp (its
// two-body revolute chain has torsional spring-dampers).
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "rigidae/so3/rotation.hpp"
#include "test_multibody_scenes.hpp"

using namespace rigidae;
using multibody::MultibodyProblem;

namespace {

struct Oscillator {
  double k = 0.0, c = 0.0, rest = 0.0, w0 = 0.0;
};

const Vec3 kAxis = Vec3(0.3, -0.2, 1.0).normalized();

Scene torsion_scene(const Oscillator& o, Coordinates coords, Equations eq, const std::string& scheme) {
  Scene s = test::multibody_base(coords, eq, scheme);
  MultibodySpec& m = *s.multibody;
  BodySpec b;
  b.name = "rotor";
  b.mass = 2.0;
  b.inertia_com << 0.4, 0.05, -0.02, 0.05, 0.7, 0.03, -0.02, 0.03, 0.9;
  b.x0_W = Vec3(0.2, -0.1, 0.4);
  b.R0_WB = so3::axis_angle_to_matrix(Vec3(1, 2, 3).normalized(), 0.7);
  b.omega0_B = b.R0_WB.transpose() * (o.w0 * kAxis);
  m.bodies.push_back(b);
  const Vec3 n = kAxis.cross(Vec3::UnitX()).normalized();
  JointSpec j = test::joint_at(m, JointType::Revolute, kGround, 0, b.x0_W, kAxis, n, "hinge");
  j.torsion_stiffness = o.k;
  j.torsion_damping = o.c;
  j.torsion_rest_angle = o.rest;
  m.joints.push_back(j);
  m.gravity_W.setZero();
  return s;
}

double axis_inertia(const Scene& s) {
  const BodySpec& b = s.multibody->bodies[0];
  const Vec3 zB = b.R0_WB.transpose() * kAxis;
  return zB.dot(b.inertia_com * zB);
}

double exact_angle(const Oscillator& o, double J, double t) {
  const double beta = o.c / (2.0 * J), wd = std::sqrt(o.k / J - beta * beta);
  const double A = -o.rest, B = (o.w0 + beta * A) / wd;
  return o.rest + std::exp(-beta * t) * (A * std::cos(wd * t) + B * std::sin(wd * t));
}

class Samples final : public StepSink {
 public:
  explicit Samples(MultibodyProblem& p) : p_(p) {}
  void on_step(double, double, int, const Eigen::VectorXd&) override {}
  void on_output(double t, const Eigen::VectorXd& y) override {
    t_.push_back(t);
    q_.push_back(p_.body_orientation(0, y.data()));
    energy_.push_back(p_.kinetic_energy(y.data()) + p_.potential_energy(y.data()));
  }
  std::vector<double> t_, energy_;
  std::vector<Vec4> q_;

 private:
  MultibodyProblem& p_;
};

// Largest angle (rad) between the run's orientations and the exact ones.
double worst_orientation_error(const Oscillator& o, const Scene& s, std::vector<double>* energy = nullptr) {
  MultibodyProblem p(s);
  Samples rec(p);
  const RunResult r = integrate(p, s.solver, s.time, rec);
  REQUIRE(r.status == RunStatus::Success);
  REQUIRE(rec.t_.size() > 10);
  const double J = axis_inertia(s);
  const Mat3 R0 = s.multibody->bodies[0].R0_WB;
  double worst = 0.0;
  for (std::size_t i = 0; i < rec.t_.size(); ++i) {
    const Mat3 R = so3::axis_angle_to_matrix(kAxis, exact_angle(o, J, rec.t_[i])) * R0;
    worst = std::max(worst, so3::quaternion_distance(rec.q_[i], so3::matrix_to_quaternion(R)));
  }
  if (energy) *energy = rec.energy_;
  return worst;
}

}  // namespace

TEST_CASE("torsion: an undamped spring is a harmonic oscillator of period 2 pi sqrt(J/k), every representation and form") {
  const Oscillator o{3.0, 0.0, 0.3, 0.5};
  for (Coordinates c : {Coordinates::EulerAngles, Coordinates::Quaternion, Coordinates::Linear})
    for (Equations e : {Equations::Lagrange, Equations::Euler}) {
      CAPTURE(to_string(c) + "/" + to_string(e));
      Scene s = torsion_scene(o, c, e, "ggl");
      const double period = 2.0 * std::numbers::pi * std::sqrt(axis_inertia(s) / o.k);
      s.time = {0.0, 1.5 * period, period / 40.0};
      s.solver.rtol = s.solver.atol = 1e-10;
      std::vector<double> energy;
      const double worst = worst_orientation_error(o, s, &energy);
      CHECK(worst < 1e-6);
      // The spring's potential is part of the energy: 1/2 J w0^2 + 1/2 k theta0^2, conserved.
      const double E0 = 0.5 * axis_inertia(s) * o.w0 * o.w0 + 0.5 * o.k * o.rest * o.rest;
      double drift = 0.0;
      for (double E : energy) drift = std::max(drift, std::abs(E - E0));
      CHECK(drift < 1e-6 * E0);
      MESSAGE(to_string(c) << "/" << to_string(e) << ": period " << period << " s, worst angle " << worst
                           << " rad, energy drift " << drift / E0);
    }
}

TEST_CASE("torsion: damping decays the swing as exp(-c t / 2J) (exact damped oscillator)") {
  const Oscillator o{4.0, 0.3, -0.4, 1.2};
  for (const char* scheme : {"index3", "index2", "index1", "baumgarte", "ggl", "projection"}) {
    CAPTURE(scheme);
    Scene s = torsion_scene(o, Coordinates::Quaternion, Equations::Euler, scheme);
    s.time = {0.0, 4.0, 0.05};
    s.solver.rtol = s.solver.atol = 1e-10;
    CHECK(worst_orientation_error(o, s) < 1e-5);
  }
}

TEST_CASE("torsion: a spring wound many turns keeps its angle's branch (theta0 = 10 rad)") {
  // The body swings between 0 and 20 rad: about three turns each way, so the
  // angle passes +-pi many times; a lost branch would jump the torque by 2 pi k.
  const Oscillator o{2.0, 0.0, 10.0, 0.0};
  Scene s = torsion_scene(o, Coordinates::Quaternion, Equations::Lagrange, "ggl");
  const double period = 2.0 * std::numbers::pi * std::sqrt(axis_inertia(s) / o.k);
  s.time = {0.0, 1.25 * period, period / 100.0};
  s.solver.rtol = s.solver.atol = 1e-10;
  std::vector<double> energy;
  CHECK(worst_orientation_error(o, s, &energy) < 1e-5);
  const double E0 = 0.5 * o.k * o.rest * o.rest;
  for (double E : energy) CHECK(std::abs(E - E0) < 1e-6 * E0);
}
