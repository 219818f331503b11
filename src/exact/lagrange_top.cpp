#include "rigidae/exact/lagrange_top.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "periodic_integral.hpp"
#include "rigidae/exact/jacobi_elliptic.hpp"
#include "rigidae/so3/rotation.hpp"
#include "steady_rotation.hpp"

namespace rigidae::exact {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
constexpr double kPi = std::numbers::pi;

// c0 + c1 x + c2 x^2 + c3 x^3.
struct Cubic {
  double c0, c1, c2, c3;
  double operator()(double x) const { return c0 + x * (c1 + x * (c2 + x * c3)); }
  double slope(double x) const { return c1 + x * (2.0 * c2 + x * 3.0 * c3); }
};

// The root of f in [lo, hi] where f(lo) <= 0 <= f(hi) (either order of the
// ends), by Newton steps kept inside a shrinking bracket (bisection when a
// step leaves it), to full precision.
double bracketed_root(const Cubic& f, double lo, double hi) {
  double flo = f(lo);
  double fhi = f(hi);
  if (flo == 0.0) return lo;
  if (fhi == 0.0) return hi;
  if ((flo > 0.0) == (fhi > 0.0)) return std::abs(flo) < std::abs(fhi) ? lo : hi;  // no sign change: best end
  double x = 0.5 * (lo + hi);
  for (int i = 0; i < 200; ++i) {
    const double fx = f(x);
    if (fx == 0.0) return x;
    if ((fx > 0.0) == (fhi > 0.0)) {
      hi = x;
      fhi = fx;
    } else {
      lo = x;
      flo = fx;
    }
    const double d = f.slope(x);
    double next = d != 0.0 ? x - fx / d : 0.5 * (lo + hi);
    if (!(next > std::min(lo, hi) && next < std::max(lo, hi))) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 2.0 * kEpsilon * std::abs(x) || std::abs(hi - lo) <= 2.0 * kEpsilon * std::abs(x)) return next;
    x = next;
  }
  return x;
}

// A unit vector orthogonal to the unit vector n (from the axis least aligned with it).
Vec3 orthogonal_unit(const Vec3& n) {
  int i = 0;
  n.cwiseAbs().minCoeff(&i);
  Vec3 e = Vec3::Unit(i) - n(i) * n;
  return e.normalized();
}

// Working body frame (e1, e2, e_s) and space frame (x, y, up); R_{Sp,K} =
// Rz(phi) Rx(theta) Rz(psi) has the quaternion
//   (C cos(sigma/2), S cos(delta/2), S sin(delta/2), C sin(sigma/2)),
//   C = cos(theta/2) = sqrt((1 + u)/2), S = sin(theta/2) = sqrt((1 - u)/2),
//   sigma = phi + psi, delta = phi - psi.
// Near the lower pole only sigma matters and near the upper one only delta:
// their rates (see lagrange_top.hpp) each carry one of the two pole terms
// p/(1 + u), p = b + a, and q/(1 - u), q = b - a.
//
// u = u1 + D sn^2(tau), tau = lambda (t - t0) + tau0, D = u2 - u1, so
//   v = 1 + u = v1 + D sn^2,  w = 1 - u = w2 + D cn^2  (sums of positive terms).
// Pole integrals, with s = sn^2(tau):
//   int dtau / (v1 + D s) = (1/v1) [Theta_B/gamma_B + int N s/(1 + N s)],
//   Theta_B = atan(gamma_B sn/(cn dn)) (continued by pi every 2K),
//   N = v1/(u3 - u1), gamma_B^2 = (1 + D/v1)(1 + N);
// this follows from d/dtau atan(g sn/(cn dn)) = g (1 - m s^2)/((1 + P s)(1 + N s))
// with P N = m, P + N = g^2 - 1 - m, and partial fractions. The arctangent
// carries the fast swing near the pole (width sqrt(v1/D)); what remains is
// smooth. The upper pole is the same in sigma = tau - K, where
//   w = (w2 + M sn^2(sigma))/dn^2(sigma),  M = m (u3 - 1).
class LagrangeTop final : public ExactSolution {
 public:
  LagrangeTop(const Mat3& J, const Vec3& c_B, double mass, const Vec3& gravity_W, const Mat3& R0,
              const Vec3& omega0, double t0, double span)
      : t0_(t0) {
    const double l = c_B.norm();
    const Vec3 es = c_B / l;
    const double C = es.dot(J * es);
    const double A = 0.5 * (J.trace() - C);
    const double g = gravity_W.norm();
    const Vec3 up_W = -gravity_W / g;
    K_ << orthogonal_unit(es), es.cross(orthogonal_unit(es)), es;
    const Vec3 ex = orthogonal_unit(up_W);
    R_WSp_ << ex, up_W.cross(ex), up_W;

    const Vec3 up_B = R0.transpose() * up_W;
    const double u0 = up_B.dot(es);
    const double v0 = 0.5 * (up_B + es).squaredNorm();
    const double w0 = 0.5 * (up_B - es).squaredNorm();
    omega3_ = omega0.dot(es);
    const Vec3 omega_perp = omega0 - omega3_ * es;
    const Vec3 Jw = J * omega0;
    const double beta = 2.0 * mass * g * l / A;
    a_ = C * omega3_ / A;
    p_ = (up_B + es).dot(Jw) / A;  // b + a
    q_ = (up_B - es).dot(Jw) / A;  // b - a
    const double wp2 = omega_perp.squaredNorm();
    const double alpha = wp2 + beta * u0;  // (2E - C omega3^2)/A, E with V = m g l u
    const double alpha_plus_beta = wp2 + beta * v0;
    const double alpha_minus_beta = wp2 - beta * w0;

    // u' and u'' from the state, so that the cubic about u0 keeps its
    // (possibly tiny) low coefficients accurate: near steady precession
    // the two turning points are close and only these coefficients resolve them.
    const double du = up_B.dot(omega0.cross(es));
    const Vec3 torque = c_B.cross(mass * (R0.transpose() * gravity_W));
    const Vec3 domega = J.ldlt().solve(torque - omega0.cross(Jw));
    const double ddu = -(omega0.cross(up_B)).dot(omega0.cross(es)) + up_B.dot(domega.cross(es));
    // f(u0 + x) = u'^2 + 2 u'' x + (3 beta u0 - alpha - a^2) x^2 + beta x^3.
    const Cubic fS{du * du, 2.0 * ddu, 3.0 * beta * u0 - alpha - a_ * a_, beta};
    // The same cubic about the poles: f(-1 + v) and f(1 - w).
    const Cubic fB{-p_ * p_, 2.0 * alpha_plus_beta + 2.0 * a_ * p_, -(alpha + 3.0 * beta + a_ * a_), beta};
    const Cubic fT{-q_ * q_, 2.0 * alpha_minus_beta - 2.0 * a_ * q_, 3.0 * beta - alpha - a_ * a_, -beta};

    // Roots x1 <= 0 <= x2 <= x3 of fS (u_i = u0 + x_i). x3 by Newton from
    // above the Cauchy bound (monotone for a cubic with real roots), then
    // x1, x2 from the deflated quadratic x^2 + e1 x + e0, whose coefficients
    // come from c0, c1 and x3 without cancellation.
    double x3 = 1.0 + std::max({std::abs(fS.c0), std::abs(fS.c1), std::abs(fS.c2)}) / beta;
    for (int i = 0; i < 500; ++i) {
      const double step = fS(x3) / fS.slope(x3);
      if (!(step > 0.0)) break;
      x3 -= step;
      if (step <= 2.0 * kEpsilon * x3) break;
    }
    const double e0 = -fS.c0 / (beta * x3);
    const double e1 = (beta * e0 - fS.c1) / (beta * x3);
    const double sq = std::sqrt(std::max(0.0, e1 * e1 - 4.0 * e0));
    double x1, x2;
    if (e1 >= 0.0) {
      x1 = -0.5 * (e1 + sq);
      x2 = x1 != 0.0 ? e0 / x1 : 0.0;
    } else {
      x2 = 0.5 * (sq - e1);
      x1 = x2 != 0.0 ? e0 / x2 : 0.0;
    }
    x1 = std::min(x1, 0.0);
    x2 = std::max(x2, 0.0);
    D_ = x2 - x1;

    // Distances of the turning points from the poles, to full relative
    // accuracy when small (the heavy-top benchmark passes 1e-6 rad from the
    // downward vertical: v1 ~ 1e-13).
    v1_ = v0 + x1;
    if (p_ == 0.0) {
      v1_ = 0.0;
    } else if (v1_ < 0.5 * v0) {
      v1_ = bracketed_root(fB, 0.0, 0.5 * v0);
    }
    w2_ = w0 - x2;
    if (w2_ < 0.5 * w0) {
      if (q_ == 0.0)
        w2_ = alpha_minus_beta > 0.0 ? 0.0 : std::max(w2_, 0.0);
      else
        w2_ = bracketed_root(fT, 0.0, 0.5 * w0);
    }
    const double w1 = w0 - x1;
    double u3m1;  // u3 - 1
    if (q_ != 0.0 && w2_ > 0.0)
      u3m1 = q_ * q_ / (beta * w1 * w2_);  // product of fT's roots: -(1 - u1)(1 - u2)(1 - u3) = -q^2/beta
    else if (q_ == 0.0 && w2_ > 0.0)
      u3m1 = 0.0;
    else
      u3m1 = std::max(0.0, x3 - w0);
    const double u3mu1 = u3m1 + w1;
    m_ = D_ / u3mu1;
    m1_ = (u3m1 + w2_) / u3mu1;
    if (!(m1_ > 0.0)) {
      throw std::invalid_argument(
          "Lagrange top: the axis approaches the upright position asymptotically (u2 = u3 = 1), the nutation "
          "period is infinite");
    }
    lambda_ = 0.5 * std::sqrt(beta * u3mu1);
    quarter_ = complete_elliptic_k(m1_);
    if (D_ > 0.0) {
      // sn^2 = (u0 - u1)/D, cn^2 = (u2 - u0)/D, dn^2 = (u3 - u0)/(u3 - u1);
      // u' = 2 D lambda sn cn dn has the sign of tau0 in [-K, K].
      const double sn = (du < 0.0 ? -1.0 : 1.0) * std::sqrt(-x1 / D_);
      const double cn = std::sqrt(x2 / D_);
      const double dn = std::sqrt(x3 / u3mu1);
      tau0_ = jacobi_argument(sn, cn, dn, m1_);
      // The same phase from the upper turning point, sigma0 = tau0 - K, to
      // its own relative accuracy (a start close to the upper pole is close
      // to sigma = 0, where the upper arctangent is steep):
      // sn(tau - K) = -cn/dn, cn(tau - K) = k' sn/dn, dn(tau - K) = k'/dn.
      const double kp = std::sqrt(m1_);
      sigma0_T_ = jacobi_argument(-cn / dn, kp * sn / dn, kp / dn, m1_);
    } else {
      sigma0_T_ = -quarter_;
    }
    const SnCnDn e0s = jacobi_sn_cn_dn(tau0_, m_, m1_);

    // Initial sigma, delta from the quaternion of R_{Sp,K}(t0).
    const Vec4 q0 = so3::matrix_to_quaternion(R_WSp_.transpose() * R0 * K_);
    sigma0_ = 2.0 * std::atan2(q0(3), q0(0));
    delta0_ = 2.0 * std::atan2(q0(2), q0(1));

    // Lower pole: p/(1 + u).
    if (p_ == 0.0) {
      // The axis passes exactly through the downward vertical: cos(theta/2)
      // changes sign there, C = sqrt(D/2) sn with the sign it has at t0.
      lower_ = PoleMode::Signed;
      sign_C_ = e0s.sn >= 0.0 ? 1.0 : -1.0;
    } else if (v1_ <= u3mu1) {
      lower_ = PoleMode::Split;
      const double N = v1_ / u3mu1;
      gamma_B_ = std::sqrt((1.0 + D_ / v1_) * (1.0 + N));
      theta_P_ = p_ / (lambda_ * std::sqrt(v1_ * (v1_ + D_) * (1.0 + N)));
      kappa_P_ = p_ / (lambda_ * u3mu1);
      N_B_ = N;
    } else {
      lower_ = PoleMode::Direct;  // 1 + u >= v1 > u3 - u1 >= D: smooth on tau ~ 1
      kappa_P_ = p_ / lambda_;
    }
    // Upper pole: q/(1 - u).
    if (q_ == 0.0 && w2_ == 0.0) {
      upper_ = PoleMode::Signed;
      sign_S_ = e0s.cn >= 0.0 ? 1.0 : -1.0;
    } else if (q_ != 0.0 && w2_ <= u3m1) {
      upper_ = PoleMode::Split;
      const double M = m_ * u3m1;
      const double N = w2_ / u3m1;
      gamma_T_ = std::sqrt((1.0 + M / w2_) * (1.0 + N));
      theta_Q_ = (q_ / lambda_) * std::sqrt((u3m1 + w2_) / (w2_ * u3m1 * (w2_ + M)));
      kappa_Q_ = -q_ / (lambda_ * u3m1);
      N_T_ = N;
    } else {
      upper_ = PoleMode::Direct;  // 1 - u >= w2 > u3 - 1: smooth on tau ~ 1 (or q = 0: nothing to add)
      kappa_Q_ = q_ / lambda_;
    }
    rates_ = detail::PeriodicIntegral<2>([this](double tau) { return smooth_rates(tau); }, 2.0 * quarter_, 0.25);
    G0_ = rates_(tau0_);
    theta_B0_ = theta_B(tau0_, e0s);
    theta_T0_ = theta_T(sigma0_T_);

    // Round-off grows with the phases sigma, delta (~|omega| t) and tau; a
    // start close to a pole fixes sigma0 or delta0 only to eps / sin(distance).
    accuracy_ = 1e-12 + 20.0 * kEpsilon * (omega0.norm() + lambda_ * (1.0 + quarter_)) * span +
                4.0 * kEpsilon / std::sqrt(0.5 * std::min(v0, w0));
  }

  LagrangeTop(const LagrangeTop&) = delete;  // rates_ refers to this object
  LagrangeTop& operator=(const LagrangeTop&) = delete;

  std::string name() const override { return "Lagrange top (Jacobi elliptic nutation)"; }
  double accuracy() const override { return accuracy_; }

  RotationState at(double t) const override {
    const double tau = tau0_ + lambda_ * (t - t0_);
    const SnCnDn e = jacobi_sn_cn_dn(tau, m_, m1_);
    const double v = v1_ + D_ * e.sn * e.sn;
    const double w = w2_ + D_ * e.cn * e.cn;
    const Eigen::Vector2d G = rates_(tau) - G0_;
    double P = kappa_P_ * G(0);
    if (lower_ == PoleMode::Split) P += theta_P_ * (theta_B(tau, e) - theta_B0_);
    double Q = kappa_Q_ * G(1);
    if (upper_ == PoleMode::Split) Q += theta_Q_ * (theta_T(sigma0_T_ + lambda_ * (t - t0_)) - theta_T0_);
    const double drift = (omega3_ - a_) * (t - t0_);
    const double sigma = sigma0_ + drift + P;
    const double delta = delta0_ - drift + Q;

    // cos, sin of theta/2 and their rates; d(1 + u)/dt = 2 D lambda sn cn dn.
    const double dv = 2.0 * D_ * lambda_ * e.sn * e.cn * e.dn;
    const double root_half_D = std::sqrt(0.5 * D_);
    double Ch, dCh, Sh, dSh;
    if (lower_ == PoleMode::Signed) {
      Ch = sign_C_ * root_half_D * e.sn;
      dCh = sign_C_ * root_half_D * lambda_ * e.cn * e.dn;
    } else {
      Ch = std::sqrt(0.5 * v);
      dCh = dv / (4.0 * Ch);
    }
    if (upper_ == PoleMode::Signed) {
      Sh = sign_S_ * root_half_D * e.cn;
      dSh = -sign_S_ * root_half_D * lambda_ * e.sn * e.dn;
    } else {
      Sh = std::sqrt(0.5 * w);
      dSh = -dv / (4.0 * Sh);
    }
    // C sigma'/2 and S delta'/2, the pole terms as p/(2 sqrt(2v)), q/(2 sqrt(2w)): bounded.
    const double C_dsigma = 0.5 * Ch * (omega3_ - a_) + (p_ != 0.0 ? p_ / (2.0 * std::sqrt(2.0 * v)) : 0.0);
    const double S_ddelta = -0.5 * Sh * (omega3_ - a_) + (q_ != 0.0 ? q_ / (2.0 * std::sqrt(2.0 * w)) : 0.0);
    const double cs = std::cos(0.5 * sigma), ss = std::sin(0.5 * sigma);
    const double cd = std::cos(0.5 * delta), sd = std::sin(0.5 * delta);
    const Vec4 quat(Ch * cs, Sh * cd, Sh * sd, Ch * ss);
    const Vec4 dquat(dCh * cs - C_dsigma * ss, dSh * cd - S_ddelta * sd, dSh * sd + S_ddelta * cd,
                     dCh * ss + C_dsigma * cs);
    // q' = q (x) (0, omega)/2 for the body angular velocity.
    const Vec4 conj(quat(0), -quat(1), -quat(2), -quat(3));
    Vec3 omega_K = 2.0 * so3::quaternion_product(conj, dquat).tail<3>();
    omega_K.z() = omega3_;  // conserved exactly
    RotationState s;
    s.R_WB = R_WSp_ * so3::quaternion_to_matrix(quat) * K_.transpose();
    s.omega_B = K_ * omega_K;
    return s;
  }

 private:
  enum class PoleMode { Direct, Split, Signed };

  // The smooth parts of the two pole integrals (per unit tau), period 2K.
  Eigen::Vector2d smooth_rates(double tau) const {
    const SnCnDn e = jacobi_sn_cn_dn(tau, m_, m1_);
    const double s2 = e.sn * e.sn;
    const double c2 = e.cn * e.cn;
    Eigen::Vector2d r;
    r(0) = lower_ == PoleMode::Split ? s2 / (1.0 + N_B_ * s2) : 1.0 / (v1_ + D_ * s2);
    // Upper pole, split: the integrand cn^2(sigma)/(1 + N sn^2(sigma)) of
    // sigma = tau - K, written with tau's functions.
    r(1) = upper_ == PoleMode::Split ? m1_ * s2 / (e.dn * e.dn + N_T_ * c2) : 1.0 / (w2_ + D_ * c2);
    if (lower_ == PoleMode::Signed) r(0) = 0.0;
    if (upper_ == PoleMode::Signed || q_ == 0.0) r(1) = 0.0;
    return r;
  }
  // atan(gamma sn/(cn dn)) continued: + pi per 2K.
  double theta_B(double tau, const SnCnDn& e) const {
    const double j = std::round(tau / (2.0 * quarter_));
    const double sg = std::fmod(std::abs(j), 2.0) == 1.0 ? -1.0 : 1.0;
    return j * kPi + std::atan2(sg * gamma_B_ * e.sn, sg * e.cn * e.dn);
  }
  // The same for the upper pole, in sigma = tau - K (its own argument, for
  // accuracy near sigma = 0).
  double theta_T(double sigma) const {
    const double j = std::round(sigma / (2.0 * quarter_));
    const double sg = std::fmod(std::abs(j), 2.0) == 1.0 ? -1.0 : 1.0;
    const SnCnDn e = jacobi_sn_cn_dn(sigma, m_, m1_);
    return j * kPi + std::atan2(sg * gamma_T_ * e.sn, sg * e.cn * e.dn);
  }

  double t0_;
  Mat3 K_;      // body <- working (e1, e2, e_s)
  Mat3 R_WSp_;  // space <- (x, y, up)
  double omega3_ = 0.0, a_ = 0.0, p_ = 0.0, q_ = 0.0;
  double D_ = 0.0, v1_ = 0.0, w2_ = 0.0;
  double m_ = 0.0, m1_ = 1.0, lambda_ = 0.0, quarter_ = 0.0, tau0_ = 0.0;
  double sigma0_ = 0.0, delta0_ = 0.0, sigma0_T_ = 0.0;
  PoleMode lower_ = PoleMode::Direct, upper_ = PoleMode::Direct;
  double sign_C_ = 1.0, sign_S_ = 1.0;
  double gamma_B_ = 1.0, theta_P_ = 0.0, kappa_P_ = 0.0, N_B_ = 0.0;
  double gamma_T_ = 1.0, theta_Q_ = 0.0, kappa_Q_ = 0.0, N_T_ = 0.0;
  detail::PeriodicIntegral<2> rates_;
  Eigen::Vector2d G0_ = Eigen::Vector2d::Zero();
  double theta_B0_ = 0.0, theta_T0_ = 0.0;
  double accuracy_ = 0.0;
};

}  // namespace

std::unique_ptr<ExactSolution> make_lagrange_top_solution(const Mat3& J_B, const Vec3& c_B, double mass,
                                                          const Vec3& gravity_W, const Mat3& R0_WB,
                                                          const Vec3& omega0_B, double t0, double span) {
  const double l = c_B.norm();
  const double g = gravity_W.norm();
  if (!(l > 0.0) || !(g > 0.0) || !(mass > 0.0))
    throw std::invalid_argument("Lagrange top: needs a centre of mass off the pivot, gravity and a positive mass");
  const Vec3 es = c_B / l;
  const double C = es.dot(J_B * es);
  const double A = 0.5 * (J_B.trace() - C);
  const Mat3 symmetric = A * Mat3::Identity() + (C - A) * es * es.transpose();
  if ((J_B - symmetric).norm() > 1e-12 * J_B.norm()) {
    throw std::invalid_argument(fmt::format(
        "Lagrange top: the inertia about the pivot is not symmetric about the axis through the centre of mass "
        "(off by {:.2e} relative)",
        (J_B - symmetric).norm() / J_B.norm()));
  }
  const Vec3 up_B = -(R0_WB.transpose() * gravity_W) / g;
  const Vec3 omega_perp = omega0_B - omega0_B.dot(es) * es;
  if (up_B.cross(es).norm() == 0.0) {
    // Axis exactly vertical: with no transverse rotation the top spins in
    // place (sleeping upright or hanging); otherwise the z-x-z angles start
    // at their singularity.
    if (omega_perp.norm() <= 8.0 * std::numeric_limits<double>::epsilon() * omega0_B.norm())
      return std::make_unique<SteadyRotation>(R0_WB, omega0_B, t0, span,
                                              "Lagrange top, spinning about its vertical axis (constant omega)");
    throw std::invalid_argument(
        "Lagrange top: the symmetry axis starts exactly vertical with a transverse angular velocity; this closed "
        "form starts at the singularity of its z-x-z angles (tilt the start by any small angle)");
  }
  return std::make_unique<LagrangeTop>(J_B, c_B, mass, gravity_W, R0_WB, omega0_B, t0, span);
}

}  // namespace rigidae::exact
