// Euler angles (any of the twelve sequences), Euler form.
//
//   a' = B(a)^{-1} omega_B,   J omega_B' = tau - omega_B x J omega_B.
// No constraints; B^{-1} blows up at the chart's singularity (det B = 0), so
// the chart is switched before it gets there (see EulerChart).
// Unknowns: a (3), omega_B (3).
#include "euler_chart.hpp"
#include "factories.hpp"
#include "rigid_body_derivatives.hpp"

namespace rigidae::coords {

namespace {

class EulerAnglesEuler final : public EulerAnglesRepresentation {
 public:
  using EulerAnglesRepresentation::EulerAnglesRepresentation;

  std::string name() const override { return "euler/euler"; }

  void evaluate(double /*t*/, const VecQ& q, const VecV& v, StandardTerms& out) const override {
    const Vec3 a = q.head<3>();
    const Vec3 w = v.head<3>();
    out.qdot = chart_.rate_matrix(a).partialPivLu().solve(w);
    out.M = body_.J_B;
    out.f = body_.gravity_torque_B(chart_.rotation(a)) - w.cross(body_.J_B * w);
    no_constraints(out);
  }

  // a' = B^-1 w: d/da_m = -B^-1 (dB/da_m) a'. The angles perturb R by
  // R hat(B e_m) (dR/da_m = R hat(col m)), so df/da = dtau/du B.
  void differentiate(double /*t*/, const VecQ& q, const VecV& v, const VecV& /*a*/,
                     TermDerivatives& out) const override {
    const Vec3 a = q.head<3>();
    const Vec3 w = v.head<3>();
    const Mat3 B = chart_.rate_matrix(a);
    const Eigen::PartialPivLU<Mat3> lu(B);
    const Vec3 ad = lu.solve(w);
    const std::array<Mat3, 3> dB = rate_matrix_partials(B);
    Mat3 dBad;
    for (int m = 0; m < 3; ++m) dBad.col(m) = dB[m] * ad;
    out.qdot_q = -lu.solve(dBad);
    out.N = lu.inverse();
    out.Ma_q.setZero(3, 3);
    out.f_q = gravity_torque_derivative(body_, chart_.rotation(a)) * B;
    out.f_v = gyroscopic_derivative(body_, w);
    no_constraint_derivatives(out);
  }

  void from_physical(const Mat3& R_WB, const Vec3& omega_B, VecQ& q, VecV& v) const override {
    q = so3::matrix_to_euler(chart_.sequence(), R_WB);
    v = omega_B;
  }
  Vec3 body_angular_velocity(const VecQ& /*q*/, const VecV& v) const override { return v.head<3>(); }

  std::unique_ptr<Representation> in_chart(int c) const override {
    return std::make_unique<EulerAnglesEuler>(body_, so3::all_euler_sequences().at(static_cast<std::size_t>(c)));
  }
};

}  // namespace

std::unique_ptr<Representation> make_euler_angles_euler(const RigidBodyModel& body, const so3::EulerSequence& start_chart) {
  return std::make_unique<EulerAnglesEuler>(body, start_chart);
}

}  // namespace rigidae::coords
