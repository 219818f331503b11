// The empty rotation block of a point mass (see point_mass.hpp): no
// coordinates, no velocities, no constraints; its placement is R = I.
#include "rigidae/multibody/point_mass.hpp"

namespace rigidae::multibody {

namespace {

class PointMassRotation final : public Representation {
 public:
  std::string name() const override { return "particle"; }
  int nq() const override { return 0; }
  int nv() const override { return 0; }
  int nc() const override { return 0; }
  ConstraintKind constraint_kind() const override { return ConstraintKind::None; }
  std::vector<std::string> constraint_names() const override { return {}; }
  void evaluate(double, const VecQ&, const VecV&, StandardTerms& out) const override {
    out.qdot.resize(0);
    out.M.resize(0, 0);
    out.f.resize(0);
    out.phi.resize(0);
    out.phi_q.resize(0, 0);
    out.G.resize(0, 0);
    out.gamma.resize(0);
  }
  void differentiate(double, const VecQ&, const VecV&, const VecV&, TermDerivatives& out) const override {
    out.qdot_q.resize(0, 0);
    out.N.resize(0, 0);
    out.Ma_q.resize(0, 0);
    out.f_q.resize(0, 0);
    out.f_v.resize(0, 0);
    out.gamma_q.resize(0, 0);
    out.gamma_v.resize(0, 0);
  }
  void from_physical(const Mat3&, const Vec3&, VecQ& q, VecV& v) const override {
    q.resize(0);
    v.resize(0);
  }
  Vec4 orientation(const VecQ&) const override { return Vec4(1.0, 0.0, 0.0, 0.0); }
  Mat3 placement(const VecQ&) const override { return Mat3::Identity(); }
  Vec3 body_angular_velocity(const VecQ&, const VecV&) const override { return Vec3::Zero(); }
};

class FixedRotationMap final : public RotationMap {
 public:
  int nq() const override { return 0; }
  void evaluate(const double*, int, RotationPartials& out) const override {
    out.nq = 0;
    out.R.setIdentity();
    out.d2_zero = true;
    out.d3_zero = true;
  }
};

}  // namespace

std::unique_ptr<Representation> make_point_mass_rotation() { return std::make_unique<PointMassRotation>(); }
std::unique_ptr<RotationMap> make_fixed_rotation_map() { return std::make_unique<FixedRotationMap>(); }

}  // namespace rigidae::multibody
