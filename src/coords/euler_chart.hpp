#pragma once
// The current Euler-angle chart (sequence) of an Euler-angle representation,
// the move to the most regular chart at a given orientation, and what the
// two Euler-angle representations share.
#include <array>

#include "rigidae/coords/representation.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/so3/euler_sequence.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::coords {

// One Euler-angle chart: a sequence, fixed for the chart's lifetime.
class EulerChart {
 public:
  explicit EulerChart(const so3::EulerSequence& seq) : seq_(seq) {}

  const so3::EulerSequence& sequence() const { return seq_; }
  // Its number among so3::all_euler_sequences().
  int index() const { return sequence_index(seq_); }
  Mat3 rotation(const Vec3& angles) const { return so3::euler_to_matrix(seq_, angles); }
  Mat3 rate_matrix(const Vec3& angles) const { return so3::euler_rate_matrix(seq_, angles); }
  double margin(const Vec3& angles) const { return so3::singularity_margin(seq_, angles); }

  static int sequence_index(const so3::EulerSequence& seq) {
    const auto& all = so3::all_euler_sequences();
    for (int i = 0; i < static_cast<int>(all.size()); ++i)
      if (all[i] == seq) return i;
    return 0;
  }

 private:
  so3::EulerSequence seq_;
};

// dB/d(angle m), m = 0, 1, 2, from the columns (col0, col1, e_k) of B (see
// so3::euler_rate_matrix): B does not depend on the first angle;
// d col0/db = col0 x col1 (from d Rj^T/db = -hat(e_j) Rj^T); and
// d col0/dc = col0 x e_k, d col1/dc = col1 x e_k (from d Rk^T/dc = -hat(e_k) Rk^T).
inline std::array<Mat3, 3> rate_matrix_partials(const Mat3& B) {
  const Vec3 col0 = B.col(0), col1 = B.col(1), ek = B.col(2);
  std::array<Mat3, 3> dB;
  dB[0].setZero();
  dB[1].setZero();
  dB[1].col(0) = col0.cross(col1);
  dB[2].setZero();
  dB[2].col(0) = col0.cross(ek);
  dB[2].col(1) = col1.cross(ek);
  return dB;
}

// Three angles, no constraints, charts: the parts both equation forms share.
class EulerAnglesRepresentation : public Representation {
 public:
  EulerAnglesRepresentation(const RigidBodyModel& body, const so3::EulerSequence& seq) : body_(body), chart_(seq) {}

  int nq() const override { return 3; }
  int nv() const override { return 3; }
  int nc() const override { return 0; }
  ConstraintKind constraint_kind() const override { return ConstraintKind::None; }
  std::vector<std::string> constraint_names() const override { return {}; }

  Vec4 orientation(const VecQ& q) const override { return so3::matrix_to_quaternion(placement(q)); }
  Mat3 placement(const VecQ& q) const override { return chart_.rotation(q.head<3>()); }

  int chart() const override { return chart_.index(); }
  bool has_charts() const override { return true; }
  int most_regular_chart(const VecQ& q) const override {
    return EulerChart::sequence_index(so3::most_regular_sequence(placement(q)));
  }
  double chart_margin(const VecQ& q) const override { return chart_.margin(q.head<3>()); }
  std::string chart_name() const override { return chart_.sequence().name(); }

 protected:
  // Empty constraint terms.
  static void no_constraints(StandardTerms& out) {
    out.phi.resize(0);
    out.phi_q.resize(0, 3);
    out.G.resize(0, 3);
    out.gamma.resize(0);
  }
  static void no_constraint_derivatives(TermDerivatives& out) {
    out.gamma_q.resize(0, 3);
    out.gamma_v.resize(0, 3);
  }

  RigidBodyModel body_;
  EulerChart chart_;
};

}  // namespace rigidae::coords
