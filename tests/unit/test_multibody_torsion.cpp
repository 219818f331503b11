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
// Energy: the spring's potential V = 1/2 k (theta - theta0)^2 against its
// torque (-dV/dtheta by central differences, the torque read from the
// residual), the accuracy check's energy measure on undamped springs against
// a recomputation with the angle unwrapped from the orientation, and a
// damper's loss against the integral of c theta'^2.
// Exact iteration matrices with torsion: test_multibody_jacobians.cpp (its
// two-body revolute chain has torsional spring-dampers).
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "rigidae/app/multibody_accuracy_check.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "rigidae/so3/rotation.hpp"
#include "test_multibody_scenes.hpp"

TEST_SUITE_BEGIN("unit");

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
  JointSpec j = test::joint_at(m, &joint_type("revolute"), kGround, 0, b.x0_W, kAxis, n, "hinge");
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
    // The joint is on the ground, its axis fixed in space: theta' = omega . axis.
    rate_.push_back(p_.body_omega_space(0, y.data()).dot(kAxis));
    last_y_ = y;
  }
  std::vector<double> t_, energy_, rate_;
  std::vector<Vec4> q_;
  Eigen::VectorXd last_y_;

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

// H at every accepted step from the orientation and the run's kinetic
// energy, with the spring's potential computed here: theta unwrapped from the
// rotation q q0^-1 about the (space-fixed) axis.
class StepEnergies final : public StepSink {
 public:
  StepEnergies(MultibodyProblem& p, const Oscillator& o, const Mat3& R0)
      : p_(p), o_(o), q0_inv_(so3::matrix_to_quaternion(R0.transpose())) {}
  void on_output(double, const Eigen::VectorXd& y) override {
    if (!started_) {
      started_ = true;
      H0 = energy(y);
    }
  }
  void on_step(double, double, int, const Eigen::VectorXd& y) override {
    worst = std::max(worst, std::abs(energy(y) - H0));
  }
  double H0 = 0.0, worst = 0.0;

 private:
  double energy(const Eigen::VectorXd& y) {
    const Vec4 r = so3::quaternion_product(p_.body_orientation(0, y.data()), q0_inv_);
    const double raw = 2.0 * std::atan2(r.tail<3>().dot(kAxis), r(0));
    theta_ += std::remainder(raw - theta_, 2.0 * std::numbers::pi);  // continuous with the last step
    const double d = theta_ - o_.rest;
    return p_.kinetic_energy(y.data()) + 0.5 * o_.k * d * d;
  }
  MultibodyProblem& p_;
  Oscillator o_;
  Vec4 q0_inv_;
  double theta_ = 0.0;
  bool started_ = false;
};

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

namespace {

// y with the body turned by phi about the joint axis (through its centre of
// mass, which stays), at rest, multipliers zero: a quaternion body.
Eigen::VectorXd turned(const MultibodyProblem& p, const Eigen::VectorXd& y0, double phi) {
  const multibody::BodyModel& b = p.bodies()[0];
  REQUIRE(b.coordinates == Coordinates::Quaternion);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(p.size());
  const int qo = p.groups()[b.q_group].offset;
  y.segment(qo, 7) = y0.segment(qo, 7);
  const Vec4 turn = so3::matrix_to_quaternion(so3::axis_angle_to_matrix(kAxis, phi));
  y.segment<4>(qo + 3) = so3::quaternion_product(turn, Vec4(y0.segment<4>(qo + 3)));
  return y;
}

// The generalized force of the torsional spring along a unit turn rate about
// the axis, read from the residual's dynamic rows at rest (no gravity, no
// velocity terms, zero multipliers, y' = 0: those rows hold -f): -(torque on
// the body about the axis) = k (theta - theta0).
double spring_torque_from_residual(MultibodyProblem& p, const Eigen::VectorXd& y) {
  const multibody::BodyModel& b = p.bodies()[0];
  const int qo = p.groups()[b.q_group].offset, vo = p.groups()[b.v_group].offset;
  const Vec4 q = y.segment<4>(qo + 3);
  // The rotation velocities of a unit turn rate about kAxis: in the Euler form omega_B itself.
  const Vec3 axis_B = so3::quaternion_to_matrix(q).transpose() * kAxis;
  REQUIRE(b.nvr == 3);
  REQUIRE((b.rep->body_angular_velocity(VecQ(q), VecV(axis_B)) - axis_B).norm() < 1e-14);
  Eigen::VectorXd yp = Eigen::VectorXd::Zero(p.size()), F(p.size());
  REQUIRE(p.residual(0.0, y.data(), yp.data(), F.data()));
  return -F.segment<3>(vo + 3).dot(axis_B);
}

}  // namespace

TEST_CASE("torsion: the spring's potential is the integral of its torque (-dV/dtheta by central differences)") {
  // Rest angle 10 rad: the spring is wound by more than a turn, so V and the
  // torque carry the angle's winding, not its value modulo 2 pi.
  const Oscillator o{2.5, 0.0, 10.0, 0.0};
  const Scene s = torsion_scene(o, Coordinates::Quaternion, Equations::Euler, "ggl");
  auto check_at = [&](MultibodyProblem& p, const Eigen::VectorXd& y0, double phi, double theta_expected,
                      double theta_accuracy) {
    const double h = 1e-5;
    const double V_plus = p.potential_energy(turned(p, y0, phi + h).data());
    const double V_minus = p.potential_energy(turned(p, y0, phi - h).data());
    const double dV = (V_plus - V_minus) / (2.0 * h);
    const Eigen::VectorXd y = turned(p, y0, phi);
    const double torque = spring_torque_from_residual(p, y);
    // Central differences: O(h^2) k-free error (V is quadratic in theta), rounding V eps / h.
    CHECK(std::abs(torque + dV) < 1e-8 * std::max(1.0, std::abs(dV)));
    // V = 1/2 k (theta - theta0)^2 on the right winding (a wrong one is off by 2 pi k |theta - theta0|).
    const double d = theta_expected - o.rest;
    CHECK(std::abs(p.potential_energy(y.data()) - 0.5 * o.k * d * d) <
          1e-13 * 0.5 * o.k * d * d + o.k * std::abs(d) * theta_accuracy);
    MESSAGE("theta " << theta_expected << " rad: -dV/dtheta " << -dV << " N m, spring torque " << -torque << " N m");
  };
  SUBCASE("at the start's branch (theta in (-pi, pi))") {
    MultibodyProblem p(s);
    Eigen::VectorXd y0(p.size()), yp0(p.size());
    p.initial_state(0.0, y0, yp0);
    for (double phi : {-2.9, -1.0, 0.0, 0.4, 3.0}) check_at(p, y0, phi, phi, 1e-15);
  }
  SUBCASE("after winding past pi twice (theta about 7 rad, followed by the run)") {
    // Released from theta = 0 it swings to 2 theta0 = 20 rad: theta(t) = 10 - 10 cos(W t).
    Scene run = s;
    const double J = axis_inertia(run), W = std::sqrt(o.k / J), t_end = std::acos(1.0 - 0.7) / W;
    run.time = {0.0, t_end, t_end / 50.0};
    run.solver.rtol = run.solver.atol = 1e-11;
    MultibodyProblem p(run);
    Samples rec(p);
    REQUIRE(integrate(p, run.solver, run.time, rec).status == RunStatus::Success);
    const double theta_end = exact_angle(o, J, t_end);
    REQUIRE(std::abs(theta_end - 7.0) < 1e-9);
    // The recorded orientation is the turn by theta_end about the axis (modulo 2 pi).
    // The run's angle is within 1e-8 rad of the exact one (measured 2e-9).
    for (double phi : {-0.3, 0.0, 0.2}) check_at(p, rec.last_y_, phi, theta_end + phi, 1e-8);
  }
}

TEST_CASE("torsion: an undamped spring keeps the energy check, and its drift is the energy's, and scales with the tolerance") {
  // Before: any torsional spring switched the energy check off. Now the
  // spring's potential is in H, and a spring wound at rest (T0 = 0, no
  // gravity) counts its energy in the scale E_s = H0. The check's measure is
  // recomputed here from every accepted step with the angle unwrapped from
  // the orientation (not torsion.cpp's atan2 of its two rows):
  //   H = T + 1/2 k (theta - theta0)^2,  theta = 2 atan2(v . axis, w) of q q0^-1.
  const struct {
    Coordinates c;
    Equations e;
  } forms[] = {{Coordinates::Quaternion, Equations::Euler},
               {Coordinates::Linear, Equations::Lagrange},
               {Coordinates::EulerAngles, Equations::Euler}};
  for (const Oscillator& o : {Oscillator{3.0, 0.0, 0.3, 0.5}, Oscillator{2.0, 0.0, 10.0, 0.0}})
    for (const auto& f : forms) {
      double drift_at[2] = {0.0, 0.0};
      for (int k = 0; k < 3; ++k) {
        const double tol = std::pow(10.0, -6.0 - 2.0 * k);
        Scene s = torsion_scene(o, f.c, f.e, "ggl");
        CAPTURE(to_string(f.c) + "/" + to_string(f.e));
        CAPTURE(o.rest);
        CAPTURE(tol);
        const double period = 2.0 * std::numbers::pi * std::sqrt(axis_inertia(s) / o.k);
        s.time = {0.0, 3.0 * period, period / 20.0};
        s.solver.rtol = s.solver.atol = tol;
        MultibodyProblem p(s);
        REQUIRE(p.conserves_energy());
        StepEnergies mine(p, o, s.multibody->bodies[0].R0_WB);
        MultibodyInvariantMonitor monitor(p, s, &mine);
        REQUIRE(integrate(p, s.solver, s.time, monitor).status == RunStatus::Success);
        const InvariantDrifts& d = monitor.drifts();
        REQUIRE(std::isfinite(d.energy));
        CHECK(d.energy > 0.0);  // a run never keeps H bit for bit
        // No gravity: E_s = T0 + V0 = H0.
        CHECK(std::abs(d.energy - mine.worst / mine.H0) <= 1e-6 * d.energy);
        // "To the tolerance's order": within three decades of tau (measured 7 to 800 tau).
        CHECK(d.energy < 2e3 * d.tolerance);
        if (k != 1) drift_at[k / 2] = d.energy;
        MESSAGE(to_string(f.c) << "/" << to_string(f.e) << "/ggl, rest " << o.rest << " rad, w0 " << o.w0
                               << " rad/s, rtol " << tol << ": |H - H0|/E_s " << d.energy << " = "
                               << d.energy / d.tolerance << " tau over " << monitor.steps() << " steps (limit "
                               << 2.0 * std::sqrt(static_cast<double>(monitor.steps())) << " tau), "
                               << std::string(monitor.warnings().empty() ? "no warning" : "warned"));
      }
      // 1e4 times tighter: the drift falls by more than 100 (measured 300 to 1e4).
      CHECK(drift_at[1] < drift_at[0] / 100.0);
    }
}

TEST_CASE("torsion: a damped spring loses exactly the energy its damper dissipates, and is not energy-checked") {
  // E0 - E(t) = integral of c theta'^2 over [0, t] (composite Simpson on the
  // output grid, theta' = omega . axis from the run).
  const Oscillator o{4.0, 0.3, -0.4, 1.2};
  Scene s = torsion_scene(o, Coordinates::Quaternion, Equations::Euler, "ggl");
  CHECK_FALSE(MultibodyProblem(s).conserves_energy());
  CHECK_FALSE(MultibodyProblem(s).energy_balance_known());  // the damper's power is not tracked
  const double dt = 2e-3;
  s.time = {0.0, 4.0, dt};
  s.solver.rtol = s.solver.atol = 1e-11;
  MultibodyProblem p(s);
  Samples rec(p);
  MultibodyInvariantMonitor monitor(p, s, &rec);
  REQUIRE(integrate(p, s.solver, s.time, monitor).status == RunStatus::Success);
  CHECK(std::isnan(monitor.drifts().energy));
  const double E0 = rec.energy_.front();
  double dissipated = 0.0, worst = 0.0;
  auto power = [&](std::size_t i) { return o.c * rec.rate_[i] * rec.rate_[i]; };
  for (std::size_t i = 2; i < rec.t_.size(); i += 2) {
    REQUIRE(std::abs(rec.t_[i] - rec.t_[i - 2] - 2.0 * dt) < 1e-12);
    dissipated += dt / 3.0 * (power(i - 2) + 4.0 * power(i - 1) + power(i));
    worst = std::max(worst, std::abs(E0 - rec.energy_[i] - dissipated));
  }
  const double lost = E0 - rec.energy_.back();
  CHECK(lost > 0.5 * E0);  // the damper takes most of it in 4 s (beta = c / 2J)
  CHECK(worst < 1e-7 * E0);
  MESSAGE("E0 " << E0 << " J, lost " << lost << " J, largest |E0 - E - integral c theta'^2| " << worst << " J");
}

TEST_SUITE_END();
