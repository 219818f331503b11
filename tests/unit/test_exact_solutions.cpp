// The closed-form solutions (free body, Lagrange top) against an independent
// integration written here: classical RK4 on (quaternion, body omega) at two
// step sizes, Richardson-extrapolated. Plus invariants, omega = the derivative
// of R, the published heavy-top value, and the textbook formulas of
// shared/design/references.md checked on the integrated motion itself.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "rigidae/exact/exact_solution.hpp"
#include "rigidae/exact/free_body.hpp"
#include "rigidae/exact/jacobi_elliptic.hpp"
#include "rigidae/exact/lagrange_top.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/rigid_body.hpp"
#include "rigidae/so3/rotation.hpp"
#include "test_scenes.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;
using namespace rigidae::exact;

namespace {

constexpr double kPi = std::numbers::pi;

// ---------------------------------------------------------------------------
// The independent reference: Euler's equations with the gravity torque and
// q' = q (x) (0, omega)/2, classical RK4 with a fixed step.

struct State {
  Vec4 q;
  Vec3 omega;
};

struct Dynamics {
  Mat3 J;
  Mat3 J_inv;
  Vec3 c;  // reference point -> centre of mass
  double mass;
  Vec3 g;

  explicit Dynamics(const Scene& s) {
    const RigidBodyModel m = make_rigid_body_model(s);
    J = m.J_B;
    J_inv = J.inverse();
    c = m.c_B;
    mass = m.mass;
    g = m.gravity_W;
  }
  State rates(const State& s) const {
    const Mat3 R = so3::quaternion_to_matrix(s.q);
    const Vec3 torque = c.cross(mass * (R.transpose() * g));
    return {0.5 * so3::quaternion_product(s.q, Vec4(0.0, s.omega.x(), s.omega.y(), s.omega.z())),
            J_inv * (torque - s.omega.cross(J * s.omega))};
  }
  State step(const State& s, double h) const {
    const auto plus = [](const State& a, double f, const State& d) { return State{a.q + f * d.q, a.omega + f * d.omega}; };
    const State k1 = rates(s);
    const State k2 = rates(plus(s, h / 2, k1));
    const State k3 = rates(plus(s, h / 2, k2));
    const State k4 = rates(plus(s, h, k3));
    State n{s.q + h / 6 * (k1.q + 2 * k2.q + 2 * k3.q + k4.q),
            s.omega + h / 6 * (k1.omega + 2 * k2.omega + 2 * k3.omega + k4.omega)};
    n.q.normalize();
    return n;
  }
};

// States at increasing `times`, steps of at most h that land on each time.
std::vector<State> integrate(const Dynamics& d, State s, double t0, const std::vector<double>& times, double h) {
  std::vector<State> out;
  double t = t0;
  for (double target : times) {
    const long n = std::max(1L, static_cast<long>(std::ceil((target - t) / h - 1e-9)));
    const double dt = (target - t) / n;
    for (long i = 0; i < n; ++i) s = d.step(s, dt);
    t = target;
    out.push_back(s);
  }
  return out;
}

// Richardson: RK4's error at h/2 is (y_{h/2} - y_h)/15 to leading order.
struct Reference {
  std::vector<double> times;
  std::vector<State> states;
  double richardson = 0.0;  // largest estimated orientation error of the h/2 run, rad
};

Reference reference_motion(const Scene& s, const std::vector<double>& times, double h) {
  const Dynamics d(s);
  const State s0{so3::matrix_to_quaternion(s.R0_WB), s.omega0_B};
  const std::vector<State> coarse = integrate(d, s0, s.time.start, times, h);
  const std::vector<State> fine = integrate(d, s0, s.time.start, times, h / 2);
  Reference r{times, {}, 0.0};
  for (std::size_t i = 0; i < times.size(); ++i) {
    State x{fine[i].q + (fine[i].q - coarse[i].q) / 15.0, fine[i].omega + (fine[i].omega - coarse[i].omega) / 15.0};
    x.q.normalize();
    r.richardson = std::max(r.richardson, so3::quaternion_distance(x.q, fine[i].q));
    r.states.push_back(x);
  }
  return r;
}

std::vector<double> sample_times(double t0, double t1, int n) {
  // Irregular spacing, so that no sample is locked to a period; the last is t1.
  std::vector<double> t;
  for (int i = 1; i <= n; ++i) t.push_back(t0 + (t1 - t0) * (i - 0.6 * std::abs(std::sin(2.1 * i + 0.4))) / n);
  t.back() = t1;
  return t;
}

struct Agreement {
  double orientation = 0.0;  // max rad
  double omega = 0.0;        // max |d omega| / max |omega|
  double richardson = 0.0;   // the reference's own estimated error, rad
};

Agreement compare(const ExactSolution& exact, const Scene& s, int samples, double h) {
  const Reference ref = reference_motion(s, sample_times(s.time.start, s.time.end, samples), h);
  Agreement a;
  a.richardson = ref.richardson;
  double omega_scale = 0.0;
  double omega_err = 0.0;
  for (std::size_t i = 0; i < ref.times.size(); ++i) {
    const RotationState e = exact.at(ref.times[i]);
    a.orientation = std::max(a.orientation, so3::rotation_distance(e.R_WB, so3::quaternion_to_matrix(ref.states[i].q)));
    omega_err = std::max(omega_err, (e.omega_B - ref.states[i].omega).norm());
    omega_scale = std::max(omega_scale, ref.states[i].omega.norm());
  }
  a.omega = omega_err / omega_scale;
  return a;
}

void check_agreement(const ExactSolution& exact, const Scene& s, int samples, double h) {
  const Agreement a = compare(exact, s, samples, h);
  MESSAGE(exact.name(), ": orientation ", a.orientation, " rad, omega ", a.omega, " relative (RK4 Richardson estimate ",
          a.richardson, " rad), accuracy() ", exact.accuracy());
  CHECK(a.richardson < 1e-10);
  CHECK(a.orientation < 1e-9);
  CHECK(a.omega < 1e-9);
  CHECK(a.orientation < 10.0 * exact.accuracy() + 2.0 * a.richardson);
}

// omega_B = vee(R^T R') with R' by central differences, Richardson-combined
// (error O(h^4)), relative to the largest |omega| seen.
double derivative_mismatch(const ExactSolution& exact, const std::vector<double>& times, double h) {
  const auto dR = [&](double t, double k) {
    const Mat3 ahead = exact.at(t + k).R_WB;
    const Mat3 behind = exact.at(t - k).R_WB;
    return Mat3((ahead - behind) / (2.0 * k));
  };
  double worst = 0.0;
  double scale = 0.0;
  for (double t : times) {
    const RotationState s = exact.at(t);
    const Mat3 Rdot = (4.0 * dR(t, h / 2) - dR(t, h)) / 3.0;
    worst = std::max(worst, (so3::vee(s.R_WB.transpose() * Rdot) - s.omega_B).norm());
    scale = std::max(scale, s.omega_B.norm());
  }
  return worst / scale;
}

// Invariants along the exact solution: energy, L in space (torque free) or
// the vertical component of L and the spin (top); relative deviations.
struct Drift {
  double energy = 0.0;
  double momentum = 0.0;
  double spin = 0.0;
};

Drift invariant_drift(const ExactSolution& exact, const Scene& s, const std::vector<double>& times) {
  const RigidBodyModel m = make_rigid_body_model(s);
  const auto energy = [&](const RotationState& x) { return m.kinetic_energy(x.omega_B) + m.potential_energy(x.R_WB); };
  const auto L_W = [&](const RotationState& x) { return Vec3(x.R_WB * (m.J_B * x.omega_B)); };
  const RotationState x0{s.R0_WB, s.omega0_B};
  const double E0 = energy(x0);
  const Vec3 L0 = L_W(x0);
  const Vec3 axis = m.c_B.norm() > 0 ? Vec3(m.c_B.normalized()) : Vec3::Zero();
  const double E_scale = m.kinetic_energy(s.omega0_B) + std::abs(m.mass * m.gravity_W.norm() * m.c_B.norm());
  Drift d;
  for (double t : times) {
    const RotationState x = exact.at(t);
    d.energy = std::max(d.energy, std::abs(energy(x) - E0) / E_scale);
    if (m.c_B.norm() == 0.0 || s.support == Support::Free)
      d.momentum = std::max(d.momentum, (L_W(x) - L0).norm() / L0.norm());
    else
      d.momentum = std::max(d.momentum, std::abs(m.up_W.dot(L_W(x) - L0)) / L0.norm());
    if (axis.norm() > 0) d.spin = std::max(d.spin, std::abs(axis.dot(x.omega_B - s.omega0_B)) / s.omega0_B.norm());
  }
  return d;
}

std::unique_ptr<ExactSolution> solve(const Scene& s) {
  std::string why;
  auto e = make_exact_solution(s, &why);
  INFO(why);
  REQUIRE(e != nullptr);
  return e;
}

Scene free_body_scene() { return io::load_scene(std::string(RIGIDAE_SOURCE_DIR) + "/problems/free_body.toml"); }

Scene free_scene(const Mat3& J, const Vec3& omega0, const Mat3& R0 = Mat3::Identity()) {
  Scene s;
  s.name = "free";
  s.support = Support::Free;
  s.body.inertia_com = J;
  s.omega0_B = omega0;
  s.R0_WB = R0;
  s.time = {0.0, 20.0, 0.02};
  return s;
}

// A heavy-top-like body (same mass, pivot inertia and spin axis body y) in a
// different start.
Scene top_scene(const Mat3& R0, const Vec3& omega0) {
  Scene s = test::heavy_top_scene();
  s.R0_WB = R0;
  s.omega0_B = omega0;
  return s;
}

// Roots of a cubic by bisection on a bracket with a sign change.
double bisect(const std::function<double(double)>& f, double lo, double hi) {
  REQUIRE((f(lo) < 0) != (f(hi) < 0));
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if ((f(mid) < 0) == (f(lo) < 0))
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

TEST_CASE("Jacobi elliptic functions obey their identities, derivatives and quarter periods") {
  // K(1/2) = Gamma(1/4)^2 / (4 sqrt(pi)), DLMF 19.20.2 / A&S table 17.1.
  CHECK(complete_elliptic_k(0.5) == doctest::Approx(1.8540746773013719).epsilon(1e-15));
  for (double m1 : {1.0, 0.7, 0.1, 3.3e-3, 1e-8, 1e-14}) {
    CAPTURE(m1);
    const double m = 1.0 - m1;
    const double K = complete_elliptic_k(m1);
    const SnCnDn e = jacobi_sn_cn_dn(K, m, m1);
    CHECK(e.sn == doctest::Approx(1.0).epsilon(1e-15));
    CHECK(e.dn == doctest::Approx(std::sqrt(m1)).epsilon(1e-13));  // dn(K) = k', even when tiny
    for (double u : {-7.3, -0.9, 0.0, 1e-9, 0.4, 2.2, 11.0}) {
      CAPTURE(u);
      const SnCnDn a = jacobi_sn_cn_dn(u, m, m1);
      CHECK(std::abs(a.sn * a.sn + a.cn * a.cn - 1.0) < 1e-15);
      CHECK(std::abs(a.dn * a.dn + m * a.sn * a.sn - 1.0) < 1e-15);
      // sn' = cn dn, cn' = -sn dn, by a fourth-order central difference.
      const double h = 1e-3;
      const auto d4 = [&](auto get) {
        return (8 * (get(jacobi_sn_cn_dn(u + h, m, m1)) - get(jacobi_sn_cn_dn(u - h, m, m1))) -
                (get(jacobi_sn_cn_dn(u + 2 * h, m, m1)) - get(jacobi_sn_cn_dn(u - 2 * h, m, m1)))) /
               (12 * h);
      };
      CHECK(d4([](const SnCnDn& x) { return x.sn; }) == doctest::Approx(a.cn * a.dn).epsilon(1e-9).scale(1));
      CHECK(d4([](const SnCnDn& x) { return x.cn; }) == doctest::Approx(-a.sn * a.dn).epsilon(1e-9).scale(1));
      // The argument is recovered from (sn, cn, dn) within (-2K, 2K].
      const double back = jacobi_argument(a.sn, a.cn, a.dn, m1);
      const double wrapped = u - 4.0 * K * std::round(u / (4.0 * K));
      if (std::abs(std::abs(wrapped) - 2.0 * K) > 1e-6) CHECK(back == doctest::Approx(wrapped).epsilon(1e-13).scale(1));
    }
  }
  // F is the inverse of the amplitude.
  CHECK(incomplete_elliptic_f(std::asin(jacobi_sn_cn_dn(0.8, 0.6, 0.4).sn), 0.6, 0.4) == doctest::Approx(0.8).epsilon(1e-15));
}

TEST_CASE("the free-body exact solution matches a tight RK integration over 20 s (problems/free_body.toml)") {
  // Near the intermediate axis: the body flips over every half polhode period.
  const Scene s = free_body_scene();
  const auto exact = solve(s);
  CHECK(exact->name() == "free body (Jacobi elliptic)");
  check_agreement(*exact, s, 80, 2e-3);
}

TEST_CASE("on the other side of the separatrix (L circling the smallest-moment axis) the exact solution matches RK") {
  const Scene s = free_scene(Vec3(2, 3, 4).asDiagonal(), Vec3(1.0, 0.5, 0.2),
                             so3::axis_angle_to_matrix(Vec3(1, -2, 0.5).normalized(), 1.1));
  const RigidBodyModel m = make_rigid_body_model(s);
  const double L2 = (m.J_B * s.omega0_B).squaredNorm();
  REQUIRE(L2 < 2.0 * m.kinetic_energy(s.omega0_B) * 3.0);  // L^2 < 2 E J_mid
  check_agreement(*solve(s), s, 80, 2e-3);
}

TEST_CASE("a free body circling its largest-moment axis, and one a hair off the unstable axis, match RK") {
  const Scene far = free_scene(Vec3(2, 3, 4).asDiagonal(), Vec3(0.3, 0.5, 2.0));
  check_agreement(*solve(far), far, 60, 2e-3);
  // 1e-7 rad/s off the middle axis: k' ~ 6e-8, the phase sits where an error
  // in the amplitude would be amplified 1e7 times.
  const Scene near = free_scene(Vec3(2, 3, 4).asDiagonal(), Vec3(1e-7, 2.0, 1e-7));
  check_agreement(*solve(near), near, 60, 2e-3);
}

TEST_CASE("a symmetric free body precesses regularly and matches RK") {
  for (const Vec3& moments : {Vec3(2.0, 2.0, 3.5), Vec3(3.0, 1.2, 3.0)}) {
    CAPTURE(moments.transpose());
    const Scene s = free_scene(moments.asDiagonal(), Vec3(0.7, -0.4, 1.5), so3::axis_rotation(0, 0.3));
    const auto exact = solve(s);
    CHECK(exact->name() == "free body, symmetric (regular precession)");
    check_agreement(*exact, s, 60, 2e-3);
  }
}

TEST_CASE("a free body with non-diagonal inertia matches RK (principal axes found and mapped back)") {
  const Mat3 Q = so3::axis_angle_to_matrix(Vec3(0.3, 1, -0.4).normalized(), 0.8);
  const Scene s = free_scene(Q * Vec3(1.5, 2.5, 4.0).asDiagonal() * Q.transpose(), Vec3(1.0, -1.5, 0.7),
                             so3::axis_angle_to_matrix(Vec3(1, 1, 1).normalized(), 0.4));
  check_agreement(*solve(s), s, 80, 2e-3);
}

TEST_CASE("a free body spinning about a principal axis, or a spherical one, turns at constant omega") {
  const Scene steady = free_scene(Vec3(2, 3, 4).asDiagonal(), Vec3(0, 2.0, 0));  // even the unstable axis
  CHECK(solve(steady)->name() == "free body, steady rotation (constant omega)");
  check_agreement(*solve(steady), steady, 20, 2e-3);
  const Scene ball = free_scene(Vec3(2, 2, 2).asDiagonal(), Vec3(0.3, 1, 2));
  check_agreement(*solve(ball), ball, 20, 2e-3);
}

TEST_CASE("a free body exactly on the separatrix is refused with a clear message") {
  // L1^2 (I2 - I1)/I1 = L3^2 (I3 - I2)/I3 = 9 exactly with I = (3, 6, 8),
  // L = (3, 3, 6): L^2 = 2 E I2.
  const Scene s = free_scene(Vec3(3, 6, 8).asDiagonal(), Vec3(1.0, 0.5, 0.75));
  CHECK_THROWS_WITH_AS(make_exact_solution(s, nullptr), doctest::Contains("separatrix"), std::invalid_argument);
}

TEST_CASE("the free body conserves energy and its angular momentum in space along the exact solution") {
  for (const Scene& s : {free_body_scene(), free_scene(Vec3(2, 3, 4).asDiagonal(), Vec3(1.0, 0.5, 0.2))}) {
    const Drift d = invariant_drift(*solve(s), s, sample_times(0.0, 20.0, 200));
    CHECK(d.energy < 1e-13);
    CHECK(d.momentum < 1e-13);
  }
}

TEST_CASE("the heavy top's exact solution (Lagrange top) matches a tight RK integration over 2 s") {
  // Spin 150 rad/s about body y; the axis swings to ~7e-7 rad of hanging
  // straight down once per nutation period (0.745 s).
  const Scene s = test::heavy_top_scene();
  const auto exact = solve(s);
  CHECK(exact->name() == "Lagrange top (Jacobi elliptic nutation)");
  check_agreement(*exact, s, 80, 2e-5);
}

TEST_CASE("the heavy top's exact quaternion at t = 2 s is the published one to 5 digits") {
  const Vec4 published(0.12295, -0.49108, 0.35043, -0.78799);  // Exudyn RK4, scalar first, R_WB
  Vec4 q = so3::matrix_to_quaternion(solve(test::heavy_top_scene())->at(2.0).R_WB);
  if (q.dot(published) < 0) q = -q;
  MESSAGE("exact q(2 s) = (", q(0), ", ", q(1), ", ", q(2), ", ", q(3), ")");
  CHECK((q - published).cwiseAbs().maxCoeff() < 5e-6);
}

TEST_CASE("the heavy top conserves energy, vertical angular momentum and spin along the exact solution") {
  const Scene s = test::heavy_top_scene();
  const Drift d = invariant_drift(*solve(s), s, sample_times(0.0, 2.0, 400));
  CHECK(d.energy < 1e-13);
  CHECK(d.momentum < 1e-13);
  CHECK(d.spin < 1e-15);
}

TEST_CASE("Lagrange tops in general motion, passing near the upright position, and in steady precession match RK") {
  const Vec3 es(0, 1, 0);  // symmetry axis, body y
  SUBCASE("tilted, fast and wobbling") {
    const Scene s = top_scene(so3::axis_angle_to_matrix(Vec3(1, 0.3, 0).normalized(), 0.6), Vec3(2.0, 40, -3.0));
    check_agreement(*solve(s), s, 60, 2e-5);
  }
  SUBCASE("rising to within 1e-4 rad of the upward vertical") {
    // b - a = 1e-8 rad/s: the upper turning point is ~1e-4 rad from the pole,
    // where the precession angle swings by pi within a few microseconds.
    const Scene base = top_scene(so3::axis_rotation(0, 1.0), Vec3::Zero());
    const Vec3 up_B = base.R0_WB.transpose() * Vec3::UnitZ();
    const double u0 = up_B.dot(es);
    const Vec3 up_perp = up_B - u0 * es;
    const double A = 15.234375, C = 0.46875, spin = 60.0;
    const double along = (C * spin * (1 - u0) + A * 1e-8) / A;
    const Scene s = top_scene(base.R0_WB, spin * es + along * up_perp / up_perp.squaredNorm() +
                                              2.5 * es.cross(up_B).normalized());
    check_agreement(*solve(s), s, 60, 2e-5);
  }
  SUBCASE("starting 1e-3 rad from hanging straight down") {
    const Scene s = top_scene(so3::axis_rotation(0, -kPi / 2 + 1e-3), Vec3(1.0, 50, 0.5));
    check_agreement(*solve(s), s, 60, 2e-5);
  }
  SUBCASE("steady precession (both turning points coincide)") {
    // A u0 W^2 - C w3 W + m g l = 0, the slow root.
    const Mat3 R0 = so3::axis_rotation(0, 0.5);
    const Vec3 up_B = R0.transpose() * Vec3::UnitZ();
    const double u0 = up_B.dot(es), A = 15.234375, C = 0.46875, mgl = 15 * 9.81, w3 = 150;
    const double W = 2 * mgl / (C * w3 + std::sqrt(C * C * w3 * w3 - 4 * A * u0 * mgl));
    const Scene s = top_scene(R0, W * (up_B - u0 * es) + w3 * es);
    check_agreement(*solve(s), s, 40, 2e-5);
    // The tilt stays put.
    for (double t : {0.3, 1.1, 1.9}) CHECK(up_B.dot(es) == doctest::Approx(Vec3::UnitZ().dot(solve(s)->at(t).R_WB * es)).epsilon(1e-12));
  }
  SUBCASE("a pendulum released from rest swings through the bottom") {
    const Scene s = top_scene(so3::axis_rotation(0, 0.3), Vec3::Zero());
    check_agreement(*solve(s), s, 40, 2e-5);
  }
}

TEST_CASE("a top spinning about its vertical axis turns at constant omega, and a vertical start with a wobble is refused") {
  Mat3 y_up;  // body y along space z
  y_up << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  const Scene sleeping = top_scene(y_up, Vec3(0, 50, 0));
  CHECK(solve(sleeping)->name() == "Lagrange top, spinning about its vertical axis (constant omega)");
  check_agreement(*solve(sleeping), sleeping, 20, 2e-5);
  const Scene wobbling = top_scene(y_up, Vec3(0.1, 50, 0));
  CHECK_THROWS_WITH_AS(make_exact_solution(wobbling, nullptr), doctest::Contains("exactly vertical"),
                       std::invalid_argument);
}

TEST_CASE("omega of every exact solution is the derivative of its rotation: R^T R' = hat(omega)") {
  const Mat3 Q = so3::axis_angle_to_matrix(Vec3(0.3, 1, -0.4).normalized(), 0.8);
  const std::vector<Scene> scenes{free_body_scene(),
                                  free_scene(Vec3(2, 3, 4).asDiagonal(), Vec3(1.0, 0.5, 0.2)),
                                  free_scene(Vec3(2, 2, 3.5).asDiagonal(), Vec3(0.7, -0.4, 1.5)),
                                  free_scene(Q * Vec3(1.5, 2.5, 4.0).asDiagonal() * Q.transpose(), Vec3(1, -1.5, 0.7)),
                                  test::heavy_top_scene()};
  for (const Scene& s : scenes) {
    const auto exact = solve(s);
    CAPTURE(exact->name());
    const double omega_max = 150.0 + 2.0;
    const double h = s.support == Support::Free ? 1e-3 : 2e-3 / omega_max;
    const double mismatch = derivative_mismatch(*exact, sample_times(s.time.start + 0.01, s.time.end, 50), h);
    MESSAGE(exact->name(), ": |vee(R^T R') - omega| / max|omega| = ", mismatch);
    CHECK(mismatch < 1e-9);
  }
}

TEST_CASE("the solution starts at the scene's initial state at scene.time.start") {
  Scene s = test::heavy_top_scene();
  s.time = {1.5, 3.5, 0.01};
  s.R0_WB = so3::axis_angle_to_matrix(Vec3(0.2, 0.1, 1).normalized(), 0.9);
  const RotationState x = solve(s)->at(1.5);
  CHECK(so3::rotation_distance(x.R_WB, s.R0_WB) < 1e-14);
  CHECK((x.omega_B - s.omega0_B).norm() < 1e-12 * s.omega0_B.norm());
  Scene f = free_body_scene();
  f.time = {-4.0, 16.0, 0.02};
  const RotationState y = solve(f)->at(-4.0);
  CHECK(so3::rotation_distance(y.R_WB, f.R0_WB) < 1e-14);
  CHECK((y.omega_B - f.omega0_B).norm() < 1e-14);
}

TEST_CASE("an asymmetric heavy top has no exact solution, and the factory says why") {
  const Scene s = test::asymmetric_top_scene(Coordinates::Quaternion, Equations::Euler);
  std::string why;
  CHECK(make_exact_solution(s, &why) == nullptr);
  CHECK(why.find("asymmetric") != std::string::npos);
  // A top symmetric about the pivot, J = diag(20, 20, 10), whose centre of
  // mass lies off the symmetry axis is not Lagrange's (with J1 = J2 = 2 J3
  // and the centre of mass in the equatorial plane it is Kovalevskaya's).
  Scene off = test::heavy_top_scene();
  off.body.mass = 1.0;
  off.body.com_B = Vec3(1.0, 0.0, 0.0);
  off.body.inertia_com = Vec3(20.0, 19.0, 9.0).asDiagonal();  // + m (|c|^2 I - c c^T) = diag(20, 20, 10)
  why.clear();
  CHECK(make_exact_solution(off, &why) == nullptr);
  CHECK(why.find("off the symmetry axis") != std::string::npos);
  CHECK(why.find("Kovalevskaya") != std::string::npos);
}

TEST_CASE("the Lagrange-top formulas of references.md hold on the integrated heavy top") {
  // u'^2 = (1 - u^2)(alpha - beta u) - (b - a u)^2, u = u1 + (u2 - u1) sn^2,
  // lambda = sqrt(beta (u3 - u1))/2, k^2 = (u2 - u1)/(u3 - u1),
  // phi' = (b - a u)/(1 - u^2); checked on RK's motion, not on the exact solution.
  const Scene s = test::heavy_top_scene();
  const RigidBodyModel m = make_rigid_body_model(s);
  const double A = m.J_B(0, 0), C = m.J_B(1, 1), w3 = s.omega0_B(1);
  const double E = m.kinetic_energy(s.omega0_B) + m.potential_energy(s.R0_WB);
  const double a = C * w3 / A, b = m.vertical_angular_momentum(s.R0_WB, s.omega0_B) / A;
  const double alpha = (2 * E - C * w3 * w3) / A, beta = 2 * m.mass * 9.81 * 1.0 / A;
  const auto f = [&](double u) { return (1 - u * u) * (alpha - beta * u) - (b - a * u) * (b - a * u); };
  const double u1 = bisect(f, -1.0, -0.5), u2 = bisect(f, -0.5, 0.5), u3 = bisect(f, 1.0, 10.0);
  const double lambda = std::sqrt(beta * (u3 - u1)) / 2, k2 = (u2 - u1) / (u3 - u1);
  const double K = complete_elliptic_k(1 - k2);
  MESSAGE("roots u1 + 1 = ", u1 + 1, ", u2 = ", u2, ", u3 = ", u3, "; nutation period 2K/lambda = ", 2 * K / lambda, " s");
  CHECK(2 * K / lambda == doctest::Approx(0.745).epsilon(1e-3));
  // u(0) = 0 = u2: tau = lambda t + K.
  const std::vector<double> times{0.1, 0.4, 0.4 + 1e-4, 0.4 + 2e-4, 1.3, 1.9};
  const Reference ref = reference_motion(s, times, 2e-5);
  const Vec3 es(0, 1, 0);
  std::vector<Vec3> axis;
  for (std::size_t i = 0; i < times.size(); ++i) {
    axis.push_back(so3::quaternion_to_matrix(ref.states[i].q) * es);
    const double u = axis.back().z();
    const SnCnDn e = jacobi_sn_cn_dn(lambda * times[i] + K, k2, 1 - k2);
    CHECK(u == doctest::Approx(u1 + (u2 - u1) * e.sn * e.sn).epsilon(1e-9).scale(1));
  }
  // Precession rate: the azimuth of the axis, phi with axis = (sin th sin phi, -sin th cos phi, cos th).
  const auto phi = [](const Vec3& x) { return std::atan2(x.x(), -x.y()); };
  const double rate = (phi(axis[3]) - phi(axis[1])) / 2e-4;
  const double u = axis[2].z();
  CHECK(rate == doctest::Approx((b - a * u) / (1 - u * u)).epsilon(1e-6));
}

TEST_CASE("the free-body angle formulas of references.md hold on the integrated free body") {
  // z-x-z angles from a space frame with e_z along L: cos(theta) = L3/|L|,
  // psi = atan2(L1, L2) (body components), phi' = |L| (L1^2/I1 + L2^2/I2)/(L1^2 + L2^2).
  const Scene s = free_body_scene();
  const Vec3 I(2, 3, 4);
  const Vec3 L_W = s.R0_WB * I.cwiseProduct(s.omega0_B);
  Mat3 R_WL;  // third column along L
  const Vec3 z = L_W.normalized();
  const Vec3 x = Vec3::UnitX().cross(z).normalized().cross(z).normalized();
  R_WL << x, z.cross(x), z;
  const double t = 7.3, h = 1e-4;
  const Reference ref = reference_motion(s, {t - h, t, t + h}, 1e-3);
  std::vector<Vec3> angles;
  for (const State& st : ref.states) {
    const Mat3 R_LB = R_WL.transpose() * so3::quaternion_to_matrix(st.q);
    angles.push_back(so3::matrix_to_euler(so3::EulerSequence{{2, 0, 2}}, R_LB));  // (phi, theta, psi)
  }
  const Vec3 L = I.cwiseProduct(ref.states[1].omega);
  CHECK(std::cos(angles[1](1)) == doctest::Approx(L(2) / L.norm()).epsilon(1e-11));
  CHECK(angles[1](2) == doctest::Approx(std::atan2(L(0), L(1))).epsilon(1e-10));
  const double rate = (angles[2](0) - angles[0](0)) / (2 * h);
  const double formula = L.norm() * (L(0) * L(0) / I(0) + L(1) * L(1) / I(1)) / (L(0) * L(0) + L(1) * L(1));
  CHECK(rate == doctest::Approx(formula).epsilon(1e-7));
}

TEST_CASE("an exact-solution evaluation costs microseconds") {
  for (const Scene& s : {free_body_scene(), test::heavy_top_scene()}) {
    const auto exact = solve(s);
    const int n = 2000;
    double sink = 0.0;
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) sink += exact->at(s.time.start + (s.time.end - s.time.start) * i / n).R_WB(0, 0);
    const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count() / n;
    MESSAGE(exact->name(), ": ", us, " us per at(t) (checksum ", sink, ")");
    CHECK(us < 100.0);
  }
}

TEST_SUITE_END();
