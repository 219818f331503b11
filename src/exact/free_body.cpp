#include "rigidae/exact/free_body.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "periodic_integral.hpp"
#include "rigidae/exact/jacobi_elliptic.hpp"
#include "rigidae/so3/rotation.hpp"
#include "steady_rotation.hpp"

namespace rigidae::exact {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// The rotation N with third row n (|n| = 1): N = Rx(theta) Rz(psi) with
// n = (sin theta sin psi, sin theta cos psi, cos theta), built without
// trigonometric calls. For R_LK = Rz(phi) N(n), R_LK^T e_z = n: the body
// direction of L is n whatever phi, and the body angular velocity is
// phi' n + theta' (cos psi, -sin psi, 0) + psi' e_z, whose first two
// components give phi' = (omega_x n_x + omega_y n_y)/(n_x^2 + n_y^2).
Mat3 frame_with_third_row(Vec3 n) {
  n.normalize();
  const double st = std::hypot(n.x(), n.y());
  const double ct = n.z();
  const double sp = n.x() / st;
  const double cp = n.y() / st;
  Mat3 N;
  N << cp, -sp, 0.0,        //
      ct * sp, ct * cp, -st,  //
      n.x(), n.y(), ct;
  return N;
}

// Principal axes as a proper rotation (columns), moments ascending.
void principal_axes(const Mat3& J, Vec3& moments, Mat3& Q) {
  Eigen::SelfAdjointEigenSolver<Mat3> es(J);
  if (es.info() != Eigen::Success) throw std::invalid_argument("free body: inertia eigen-decomposition failed");
  moments = es.eigenvalues();
  Q = es.eigenvectors();
  if (Q.determinant() < 0.0) Q.col(2) = -Q.col(2);
  if (!(moments(0) > 0.0)) throw std::invalid_argument("free body: inertia is not positive definite");
}

// Working frame whose z axis is principal axis `z_axis`: the cyclic order
// (z+1, z+2, z) keeps it right-handed. Columns: working axes in body components.
Mat3 working_frame(const Mat3& Q, int z_axis) {
  Mat3 K;
  K << Q.col((z_axis + 1) % 3), Q.col((z_axis + 2) % 3), Q.col(z_axis);
  return K;
}
Vec3 to_working(const Vec3& principal, int z_axis) {
  return Vec3(principal((z_axis + 1) % 3), principal((z_axis + 2) % 3), principal(z_axis));
}

// R_WB(t) = R_WL Rz(phi(t)) N(n_K(t)) K^T: L is fixed in space (R_WL's
// third column), the body sees it along n_K, phi is the angle about it.
// Subclasses supply omega in the working frame and phi.
class PoinsotMotion : public ExactSolution {
 public:
  RotationState at(double t) const override {
    double phi = 0.0;
    const Vec3 w = omega_working(t, &phi);
    const Vec3 n = inertia_K_.cwiseProduct(w);
    RotationState s;
    s.R_WB = R_WL_ * so3::axis_rotation(2, phi) * frame_with_third_row(n) * K_.transpose();
    s.omega_B = K_ * w;
    return s;
  }
  double accuracy() const override { return accuracy_; }

 protected:
  // Call last in the subclass constructor, when omega_working works.
  void anchor(const Mat3& R0_WB, double t0) {
    double phi0 = 0.0;
    const Vec3 w0 = omega_working(t0, &phi0);
    R_WL_ = R0_WB * K_ * (so3::axis_rotation(2, phi0) * frame_with_third_row(inertia_K_.cwiseProduct(w0))).transpose();
  }
  virtual Vec3 omega_working(double t, double* phi) const = 0;

  Mat3 K_;           // body <- working
  Vec3 inertia_K_;   // principal moments in working order
  double accuracy_ = 0.0;

 private:
  Mat3 R_WL_;
};

// Two equal moments It about the working x, y axes, Is about z: omega_z is
// constant, (omega_x, omega_y) turns at Omega = (Is - It) omega_z / It in the
// body, and phi' = |L| / It (the formula above with n = J omega / |L|).
class SymmetricFreeBody final : public PoinsotMotion {
 public:
  SymmetricFreeBody(const Mat3& Q, const Vec3& I, int axis, const Mat3& R0, const Vec3& omega0_B, double t0,
                    double span)
      : t0_(t0) {
    K_ = working_frame(Q, axis);
    const double It = 0.5 * (I((axis + 1) % 3) + I((axis + 2) % 3));
    inertia_K_ = Vec3(It, It, I(axis));
    w0_ = K_.transpose() * omega0_B;
    body_rate_ = (I(axis) - It) * w0_.z() / It;
    phi_rate_ = inertia_K_.cwiseProduct(w0_).norm() / It;
    // Round-off of the rates' phases: a few eps per radian turned.
    accuracy_ = 1e-14 + 20.0 * kEps * (std::abs(body_rate_) + std::abs(phi_rate_)) * span;
    anchor(R0, t0);
  }
  std::string name() const override { return "free body, symmetric (regular precession)"; }

 private:
  Vec3 omega_working(double t, double* phi) const override {
    const double c = std::cos(body_rate_ * (t - t0_));
    const double s = std::sin(body_rate_ * (t - t0_));
    *phi = phi_rate_ * (t - t0_);
    return Vec3(c * w0_.x() - s * w0_.y(), s * w0_.x() + c * w0_.y(), w0_.z());
  }
  double t0_;
  Vec3 w0_;
  double body_rate_ = 0.0;
  double phi_rate_ = 0.0;
};

// I1 < I2 < I3. With the positive invariants
//   X3 = 2 E I3 - L^2 = L1^2 (I3 - I1)/I1 + L2^2 (I3 - I2)/I2,
//   X1 = L^2 - 2 E I1 = L2^2 (I2 - I1)/I2 + L3^2 (I3 - I1)/I3,
//   Delta = L^2 - 2 E I2 = L3^2 (I3 - I2)/I3 - L1^2 (I2 - I1)/I1
// (all free of the cancellation in L^2 - 2 E Ij), Landau & Lifshitz sec. 37:
// Delta > 0 (L circles axis 3):
//   w1 = A cn, w2 = s B sn, w3 = s C dn of tau = lambda (t - t0) + tau0,
//   A^2 = X3/(I1 (I3 - I1)), B^2 = X3/(I2 (I3 - I2)), C^2 = X1/(I3 (I3 - I1)),
//   lambda^2 = (I3 - I2) X1/(I1 I2 I3), m = (I2 - I1) X3/((I3 - I2) X1),
//   1 - m = (I3 - I1) Delta/((I3 - I2) X1);
// Delta < 0 (L circles axis 1): axes 1 and 3 swap roles,
//   w3 = A cn, w2 = s B sn, w1 = s C dn,
//   A^2 = X1/(I3 (I3 - I1)), B^2 = X1/(I2 (I2 - I1)), C^2 = X3/(I1 (I3 - I1)),
//   lambda^2 = (I2 - I1) X3/(I1 I2 I3), m = (I3 - I2) X1/((I2 - I1) X3),
//   1 - m = (I3 - I1) (-Delta)/((I2 - I1) X3);
// s = sign of the dn component (Euler's equations are invariant under
// flipping two components). The working z axis is the cn axis: L never
// comes near it (the dn component never vanishes), so phi' stays regular.
class EllipticFreeBody final : public PoinsotMotion {
 public:
  EllipticFreeBody(const Mat3& Q, const Vec3& I, const Mat3& R0, const Vec3& omega0_B, double t0, double span)
      : t0_(t0) {
    const Vec3 w = Q.transpose() * omega0_B;
    const Vec3 L = I.cwiseProduct(w);
    const double I1 = I(0), I2 = I(1), I3 = I(2);
    const double X3 = L(0) * L(0) * (I3 - I1) / I1 + L(1) * L(1) * (I3 - I2) / I2;
    const double X1 = L(1) * L(1) * (I2 - I1) / I2 + L(2) * L(2) * (I3 - I1) / I3;
    const double d3 = L(2) * L(2) * (I3 - I2) / I3;
    const double d1 = L(0) * L(0) * (I2 - I1) / I1;
    const double Delta = d3 - d1;
    if (std::abs(Delta) <= 8.0 * kEps * (d3 + d1)) {
      throw std::invalid_argument(fmt::format(
          "free body exactly on the separatrix (L^2 = 2 E I2 to round-off, relative {:.1e}): the polhode period is "
          "infinite and the elliptic solution degenerates; perturb omega0 slightly",
          std::abs(Delta) / (d3 + d1)));
    }
    double A2, B2, C2, lambda2;
    if (Delta > 0) {
      cn_axis_ = 0;
      dn_axis_ = 2;
      A2 = X3 / (I1 * (I3 - I1));
      B2 = X3 / (I2 * (I3 - I2));
      C2 = X1 / (I3 * (I3 - I1));
      lambda2 = (I3 - I2) * X1 / (I1 * I2 * I3);
      m_ = (I2 - I1) * X3 / ((I3 - I2) * X1);
      m1_ = (I3 - I1) * Delta / ((I3 - I2) * X1);
    } else {
      cn_axis_ = 2;
      dn_axis_ = 0;
      A2 = X1 / (I3 * (I3 - I1));
      B2 = X1 / (I2 * (I2 - I1));
      C2 = X3 / (I1 * (I3 - I1));
      lambda2 = (I2 - I1) * X3 / (I1 * I2 * I3);
      m_ = (I3 - I2) * X1 / ((I2 - I1) * X3);
      m1_ = (I3 - I1) * (-Delta) / ((I2 - I1) * X3);
    }
    const double s = w(dn_axis_) >= 0.0 ? 1.0 : -1.0;
    amp_cn_ = std::sqrt(A2);
    amp_sn_ = s * std::sqrt(B2);
    amp_dn_ = s * std::sqrt(C2);
    lambda_ = std::sqrt(lambda2);
    quarter_ = complete_elliptic_k(m1_);
    // Phase: cn(tau0) = w_cn/A, sn(tau0) = s w2/B, dn(tau0) = s w_dn/C.
    tau0_ = jacobi_argument(w(1) / amp_sn_, w(cn_axis_) / amp_cn_, w(dn_axis_) / amp_dn_, m1_);

    K_ = working_frame(Q, cn_axis_);
    inertia_K_ = to_working(I, cn_axis_);
    L_norm_ = L.norm();
    // phi' has period 2K in tau (it depends on squares of sn, cn, dn only).
    phi_integral_ = detail::PeriodicIntegral<1>(
        [this](double tau) {
          const Vec3 wk = omega_at_tau(tau);
          const Vec3 n = inertia_K_.cwiseProduct(wk) / L_norm_;
          return Eigen::Matrix<double, 1, 1>((wk.x() * n.x() + wk.y() * n.y()) / (n.x() * n.x() + n.y() * n.y()));
        },
        2.0 * quarter_, 0.25);
    G0_ = phi_integral_(tau0_)(0);
    // Round-off: tau and phi carry ~eps relative to their size; measured
    // errors stay below 1e-13 over tens of periods (see the tests).
    const double phi_rate = phi_integral_.over_one_period()(0) / (2.0 * quarter_) * lambda_;
    accuracy_ = 1e-13 + 20.0 * kEps * (lambda_ * (1.0 + quarter_) + std::abs(phi_rate) + omega0_B.norm()) * span;
    anchor(R0, t0);
  }
  EllipticFreeBody(const EllipticFreeBody&) = delete;  // phi_integral_ refers to this object
  EllipticFreeBody& operator=(const EllipticFreeBody&) = delete;

  std::string name() const override { return "free body (Jacobi elliptic)"; }

 private:
  Vec3 omega_at_tau(double tau) const {
    const SnCnDn e = jacobi_sn_cn_dn(tau, m_, m1_);
    Vec3 wp;
    wp(cn_axis_) = amp_cn_ * e.cn;
    wp(1) = amp_sn_ * e.sn;
    wp(dn_axis_) = amp_dn_ * e.dn;
    return to_working(wp, cn_axis_);
  }
  Vec3 omega_working(double t, double* phi) const override {
    const double tau = tau0_ + lambda_ * (t - t0_);
    *phi = (phi_integral_(tau)(0) - G0_) / lambda_;
    return omega_at_tau(tau);
  }

  double t0_;
  int cn_axis_ = 0;
  int dn_axis_ = 2;
  double amp_cn_ = 0.0, amp_sn_ = 0.0, amp_dn_ = 0.0;
  double lambda_ = 0.0, m_ = 0.0, m1_ = 1.0, quarter_ = 0.0, tau0_ = 0.0;
  double L_norm_ = 0.0;
  detail::PeriodicIntegral<1> phi_integral_;
  double G0_ = 0.0;
};

}  // namespace

std::unique_ptr<ExactSolution> make_free_body_solution(const Mat3& J_B, const Mat3& R0_WB, const Vec3& omega0_B,
                                                      double t0, double span) {
  Vec3 I;
  Mat3 Q;
  principal_axes(J_B, I, Q);
  const Vec3 L = J_B * omega0_B;
  // omega along a principal axis (or a spherical body): L and omega stay
  // fixed in the body, the body turns at constant omega.
  const double tol = 1e-12 * I(2);
  if (I(2) - I(0) <= tol || omega0_B.cross(L).norm() <= 8.0 * kEps * omega0_B.norm() * L.norm())
    return std::make_unique<SteadyRotation>(R0_WB, omega0_B, t0, span, "free body, steady rotation (constant omega)");
  if (I(1) - I(0) <= tol) return std::make_unique<SymmetricFreeBody>(Q, I, 2, R0_WB, omega0_B, t0, span);
  if (I(2) - I(1) <= tol) return std::make_unique<SymmetricFreeBody>(Q, I, 0, R0_WB, omega0_B, t0, span);
  return std::make_unique<EllipticFreeBody>(Q, I, R0_WB, omega0_B, t0, span);
}

}  // namespace rigidae::exact
