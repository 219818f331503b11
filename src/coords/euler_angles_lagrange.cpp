// Euler angles (any of the twelve sequences), Lagrange form.
//
// omega_B = B(a) a' and d(omega_B)/dt = B a'' + b(a, a') (so3::euler_rate_bias),
// so T = 1/2 a'^T B^T J B a' and Lagrange's equations are B^T times Euler's:
//   M(a) a'' = B^T (tau - omega x J omega - J b),   M = B^T J B
// (products of sines and cosines). No constraints; the chart is singular
// where det B = 0 and is switched before it gets there (see EulerChart).
// Unknowns: a (3), v = a' (3).
#include "euler_chart.hpp"
#include "factories.hpp"
#include "rigid_body_derivatives.hpp"

namespace rigidae::coords {

namespace {

class EulerAnglesLagrange final : public EulerAnglesRepresentation {
 public:
  using EulerAnglesRepresentation::EulerAnglesRepresentation;

  std::string name() const override { return "euler/lagrange"; }

  void evaluate(double /*t*/, const VecQ& q, const VecV& v, StandardTerms& out) const override {
    const Vec3 a = q.head<3>();
    const Vec3 ad = v.head<3>();
    const Mat3 B = chart_.rate_matrix(a);
    const Vec3 w = B * ad;
    const Vec3 bias = so3::euler_rate_bias(chart_.sequence(), a, ad);
    out.qdot = v;
    out.M = B.transpose() * body_.J_B * B;
    out.f = B.transpose() * (body_.gravity_torque_B(chart_.rotation(a)) - w.cross(body_.J_B * w) - body_.J_B * bias);
    no_constraints(out);
  }

  // With h = tau - w x J w - J bias, w = B a', f = B^T h, dB_m = dB/da_m and
  // bias = (a'_0 col0 + a'_1 col1) x a'_2 e_k + a'_0 a'_1 col0 x col1:
  //   d(M x)/da_m = dB_m^T J B x + B^T J dB_m x
  //   df/da_m     = dB_m^T h + B^T (dtau/du B e_m + D(w) dB_m a' - J dbias/da_m)
  //   df/da'      = B^T (D(w) B - J dbias/da')
  // where D(w) is the gyroscopic derivative and R moves by R hat(B e_m).
  void differentiate(double /*t*/, const VecQ& q, const VecV& v, const VecV& acc,
                     TermDerivatives& out) const override {
    const Vec3 a = q.head<3>();
    const Vec3 ad = v.head<3>();
    const Vec3 x = acc.head<3>();
    const Mat3& J = body_.J_B;
    const Mat3 B = chart_.rate_matrix(a);
    const std::array<Mat3, 3> dB = rate_matrix_partials(B);
    const Vec3 col0 = B.col(0), col1 = B.col(1), ek = B.col(2);
    const Vec3 w = B * ad;
    const Vec3 bias = so3::euler_rate_bias(chart_.sequence(), a, ad);
    const Vec3 h = body_.gravity_torque_B(chart_.rotation(a)) - w.cross(J * w) - J * bias;
    const Mat3 D = gyroscopic_derivative(body_, w);
    const Mat3 dtau_dangles = gravity_torque_derivative(body_, chart_.rotation(a)) * B;
    const Vec3 JBx = J * (B * x);

    out.qdot_q.setZero(3, 3);
    out.N.setIdentity(3, 3);
    out.Ma_q.resize(3, 3);
    out.f_q.resize(3, 3);
    for (int m = 0; m < 3; ++m) {
      const Vec3 dcol0 = dB[m].col(0), dcol1 = dB[m].col(1);
      const Vec3 dbias = (ad(0) * dcol0 + ad(1) * dcol1).cross(ad(2) * ek) +
                         (ad(0) * ad(1)) * (dcol0.cross(col1) + col0.cross(dcol1));
      out.Ma_q.col(m) = dB[m].transpose() * JBx + B.transpose() * (J * (dB[m] * x));
      out.f_q.col(m) = dB[m].transpose() * h + B.transpose() * (dtau_dangles.col(m) + D * (dB[m] * ad) - J * dbias);
    }
    Mat3 dbias_drates;
    dbias_drates.col(0) = col0.cross(ad(2) * ek) + ad(1) * col0.cross(col1);
    dbias_drates.col(1) = col1.cross(ad(2) * ek) + ad(0) * col0.cross(col1);
    dbias_drates.col(2) = (ad(0) * col0 + ad(1) * col1).cross(ek);
    out.f_v = B.transpose() * (D * B - J * dbias_drates);
    no_constraint_derivatives(out);
  }

  void from_physical(const Mat3& R_WB, const Vec3& omega_B, VecQ& q, VecV& v) const override {
    const Vec3 a = so3::matrix_to_euler(chart_.sequence(), R_WB);
    q = a;
    v = chart_.rate_matrix(a).partialPivLu().solve(omega_B);
  }
  Vec3 body_angular_velocity(const VecQ& q, const VecV& v) const override {
    return chart_.rate_matrix(q.head<3>()) * v.head<3>();
  }

  std::unique_ptr<Representation> in_chart(int c) const override {
    return std::make_unique<EulerAnglesLagrange>(body_, so3::all_euler_sequences().at(static_cast<std::size_t>(c)));
  }
};

}  // namespace

std::unique_ptr<Representation> make_euler_angles_lagrange(const RigidBodyModel& body, const so3::EulerSequence& start_chart) {
  return std::make_unique<EulerAnglesLagrange>(body, start_chart);
}

}  // namespace rigidae::coords
