// Assembled starts: see include/rigidae/multibody/assembly.hpp for the
// equations. Runs once per run before the problem is built, on the scene's
// physical poses (not on any representation's coordinates), so every
// coordinate set and scheme starts from the same assembled mechanism.
#include "rigidae/multibody/assembly.hpp"

#include <Eigen/SparseCholesky>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "rigidae/core/error.hpp"
#include "rigidae/model/joint_type.hpp"
#include "rigidae/multibody/constraint_rows.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::multibody {

namespace {

using Sparse = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

struct Pose {
  Vec3 x;
  Mat3 R;
};

// A body held at a pivot o turns about it only: x = o + R c, c (body frame)
// fixed, so its unknowns are dtheta alone and a point's gradient carries the
// lever from the pivot (its translation columns stay zero).
struct PivotOf {
  bool pivoted = false;
  Vec3 o = Vec3::Zero();
  Vec3 c = Vec3::Zero();
};

// One row of one joint, with its unit scale (L for rows with a point, 1 else).
struct Row {
  int joint;
  const ConstraintRow* row;
  double scale;
};

Vec3 space_vector(const BodyVector& u, const std::vector<Pose>& poses) {
  if (u.body == kGround) return u.s;
  const Pose& p = poses[static_cast<std::size_t>(u.body)];
  return u.point ? Vec3(p.x + p.R * u.s) : Vec3(p.R * u.s);
}

// d(space vector)/d(dx, dtheta) of u's body, times coeff * other, added to
// the row's gradient (6 columns per body). A pivoted body's point turns with
// its lever from the pivot, x + R s - o, and has no translation columns.
void add_gradient(const BodyVector& u, const Vec3& other, double coeff, const std::vector<Pose>& poses,
                  const std::vector<PivotOf>& pivots, std::vector<std::pair<int, double>>& grad) {
  if (u.body == kGround) return;
  const auto b = static_cast<std::size_t>(u.body);
  const Pose& p = poses[b];
  const bool pivoted = pivots[b].pivoted;
  const Vec3 lever = u.point && pivoted ? Vec3(p.x - pivots[b].o + p.R * u.s) : Vec3(p.R * u.s);
  const int o = 6 * u.body;
  if (u.point && !pivoted)
    for (int k = 0; k < 3; ++k) grad.emplace_back(o + k, coeff * other(k));
  // d(r) = dtheta x r: other . (dtheta x r) = dtheta . (r x other)
  const Vec3 g = lever.cross(other);
  for (int k = 0; k < 3; ++k) grad.emplace_back(o + 3 + k, coeff * g(k));
}

bool has_point(const ConstraintRow& r) {
  for (int t = 0; t < r.n_terms; ++t)
    if (r.terms[t].a.point || r.terms[t].b.point) return true;
  return false;
}

class Assembler {
 public:
  Assembler(MultibodySpec& spec) : spec_(spec), nb_(static_cast<int>(spec.bodies.size())) {
    for (const JointSpec& j : spec.joints) {
      if (j.body_a != kGround) L_ = std::max(L_, j.point_a.norm());
      if (j.body_b != kGround) L_ = std::max(L_, j.point_b.norm());
    }
    if (!(L_ > 0.0)) L_ = 1.0;
    for (const JointSpec& j : spec.joints) {
      rows_of_joint_.emplace_back();
      j.type->rows(j, rows_of_joint_.back());
    }
    for (int j = 0; j < static_cast<int>(rows_of_joint_.size()); ++j)
      for (const ConstraintRow& r : rows_of_joint_[j]) rows_.push_back({j, &r, has_point(r) ? L_ : 1.0});
    held_.assign(nb_, 0);
    for (int b : spec.assembly.held) held_[b] = 1;
    for (const BodySpec& b : spec.bodies) {
      PivotOf pv;
      if (b.pivot_W) {
        // The lever is the body's geometry: taken from the given pose (a
        // guess may be any rotation about the pivot), kept while it turns.
        pv = {true, *b.pivot_W, b.com_from_pivot_B.value_or(Vec3(b.R0_WB.transpose() * (b.x0_W - *b.pivot_W)))};
        poses_.push_back({pv.o + b.R0_WB * pv.c, b.R0_WB});
      } else {
        poses_.push_back({b.x0_W, b.R0_WB});
      }
      pivots_.push_back(pv);
    }
  }

  AssemblyReport run() {
    AssemblyReport rep;
    rep.done = true;
    rep.held = spec_.assembly.held;
    const std::vector<Pose> given = poses_;
    Eigen::VectorXd phi = misses();
    rep.initial_miss = largest_unscaled(phi);
    double merit = phi.size() > 0 ? phi.cwiseAbs().maxCoeff() : 0.0;  // no rows: nothing to assemble
    for (int it = 0; it < kMaxIterations && merit > kConverged; ++it) {
      const Sparse G = gradient();
      const Eigen::VectorXd dz = least_change(G, phi, false);
      const std::vector<Pose> before = poses_;
      double step = 1.0;
      bool accepted = false;
      for (int halving = 0; halving < 30; ++halving, step *= 0.5) {
        poses_ = before;
        move(dz, step);
        const Eigen::VectorXd trial = misses();
        const double m = trial.cwiseAbs().maxCoeff();
        if (m < merit) {
          phi = trial;
          merit = m;
          accepted = true;
          break;
        }
      }
      rep.iterations = it + 1;
      if (!accepted) {
        poses_ = before;
        break;
      }
    }
    rep.final_miss = largest_unscaled(phi);
    if (rep.final_miss > spec_.start_tolerance) refuse(phi, rep);

    // Velocities: the space twists, held bodies kept.
    Eigen::VectorXd V(6 * nb_);
    for (int i = 0; i < nb_; ++i) {
      V.segment<3>(6 * i) = spec_.bodies[i].v0_W;
      V.segment<3>(6 * i + 3) = spec_.bodies[i].R0_WB * spec_.bodies[i].omega0_B;  // the given R: the guess's
    }
    const Eigen::VectorXd V_given = V;
    const Sparse G = gradient();
    Eigen::VectorXd rate = G * V;
    rep.initial_velocity_miss = largest_unscaled(rate);
    for (int pass = 0; pass < 2 && rate.size() > 0; ++pass) {  // a second pass for round-off of redundant rows
      V += least_change(G, rate, true);
      rate = G * V;
    }
    rep.final_velocity_miss = largest_unscaled(rate);
    // The held bodies keep their angular velocities: when the joints allow
    // no such motion the others cannot make up for it, and the start would
    // change the held rates after all (the DAE's own projection).
    const double velocity_limit = spec_.start_tolerance * std::max(1.0, V_given.cwiseAbs().maxCoeff());
    if (!spec_.assembly.held.empty() && rep.final_velocity_miss > velocity_limit)
      refuse_velocities(rep);
    // A pivoted body's centre of mass moves with its rotation about the pivot.
    for (int i = 0; i < nb_; ++i)
      if (pivots_[i].pivoted)
        V.segment<3>(6 * i) = Vec3(V.segment<3>(6 * i + 3)).cross(poses_[i].x - pivots_[i].o);

    for (int i = 0; i < nb_; ++i) {
      BodySpec& b = spec_.bodies[i];
      const Vec3 omega_W = V.segment<3>(6 * i + 3);
      {
        AssembledBody a;
        a.body = i;
        a.moved_m = (poses_[i].x - given[i].x).norm();
        a.turned_rad = so3::rotation_distance(poses_[i].R, given[i].R);
        a.velocity_change = (V - V_given).segment<3>(6 * i).norm();
        a.angular_velocity_change = (V - V_given).segment<3>(6 * i + 3).norm();
        rep.bodies.push_back(a);
      }
      b.x0_W = poses_[i].x;
      b.R0_WB = poses_[i].R;
      b.v0_W = V.segment<3>(6 * i);
      b.omega0_B = poses_[i].R.transpose() * omega_W;
      if (pivots_[i].pivoted) b.com_from_pivot_B = pivots_[i].c;
    }
    rep.note = describe(rep);
    return rep;
  }

 private:
  static constexpr int kMaxIterations = 100;
  static constexpr double kConverged = 1e-15;  // scaled rows: relative to L

  Eigen::VectorXd misses() const {
    Eigen::VectorXd phi(static_cast<int>(rows_.size()));
    for (int r = 0; r < static_cast<int>(rows_.size()); ++r) {
      const ConstraintRow& row = *rows_[r].row;
      double v = row.constant;
      for (int t = 0; t < row.n_terms; ++t)
        v += row.terms[t].coeff * space_vector(row.terms[t].a, poses_).dot(space_vector(row.terms[t].b, poses_));
      phi(r) = v / rows_[r].scale;
    }
    return phi;
  }

  double largest_unscaled(const Eigen::VectorXd& scaled) const {
    double m = 0.0;
    for (int r = 0; r < scaled.size(); ++r) m = std::max(m, std::abs(scaled(r)) * rows_[r].scale);
    return m;
  }

  Sparse gradient() const {
    std::vector<Triplet> trip;
    std::vector<std::pair<int, double>> grad;
    for (int r = 0; r < static_cast<int>(rows_.size()); ++r) {
      const ConstraintRow& row = *rows_[r].row;
      grad.clear();
      for (int t = 0; t < row.n_terms; ++t) {
        const DotTerm& term = row.terms[t];
        const Vec3 a = space_vector(term.a, poses_), b = space_vector(term.b, poses_);
        add_gradient(term.a, b, term.coeff, poses_, pivots_, grad);
        add_gradient(term.b, a, term.coeff, poses_, pivots_, grad);
      }
      for (const auto& [c, v] : grad) trip.emplace_back(r, c, v / rows_[r].scale);
    }
    Sparse G(static_cast<int>(rows_.size()), 6 * nb_);
    G.setFromTriplets(trip.begin(), trip.end());  // sums the duplicates of a body seen twice in a row
    return G;
  }

  // W^-1 as a sparse block-diagonal matrix. A held body's blocks are zero
  // (its pose and angular velocity stay as given), except its translation at
  // the velocity level: its centre-of-mass velocity follows its joints (a
  // crank needs only its angular velocity). A pivoted body has no
  // translation block; its rotation block is the inverse inertia about the
  // pivot, J_o = J_c + m (|c|^2 I - c c^T).
  Sparse inverse_metric(bool velocity_level) const {
    std::vector<Triplet> trip;
    for (int i = 0; i < nb_; ++i) {
      const BodySpec& b = spec_.bodies[i];
      const PivotOf& pv = pivots_[i];
      if (held_[i] && !velocity_level) continue;
      if (!pv.pivoted)
        for (int k = 0; k < 3; ++k) trip.emplace_back(6 * i + k, 6 * i + k, 1.0 / b.mass);
      if (held_[i] || b.particle) continue;  // a particle has no rotation: its angle columns stay zero
      const Mat3 J = pv.pivoted ? Mat3(b.inertia_com + b.mass * (pv.c.squaredNorm() * Mat3::Identity() -
                                                                   pv.c * pv.c.transpose()))
                                : b.inertia_com;
      const Mat3 Jinv = poses_[i].R * J.inverse() * poses_[i].R.transpose();
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) trip.emplace_back(6 * i + 3 + r, 6 * i + 3 + c, Jinv(r, c));
    }
    Sparse Winv(6 * nb_, 6 * nb_);
    Winv.setFromTriplets(trip.begin(), trip.end());
    return Winv;
  }

  // dz = -W^-1 G^T (G W^-1 G^T + mu I)^-1 r: the least change in the mass
  // metric that cancels r to first order (rows only the held bodies touch
  // contribute nothing: their W^-1 G^T columns are zero).
  Eigen::VectorXd least_change(const Sparse& G, const Eigen::VectorXd& r, bool velocity_level) const {
    const Sparse Winv = inverse_metric(velocity_level);
    const Sparse WGt = Winv * Sparse(G.transpose());
    Sparse A = G * WGt;
    double dmax = 0.0;
    for (int k = 0; k < A.rows(); ++k) dmax = std::max(dmax, A.coeff(k, k));
    const double mu = 1e-12 * std::max(dmax, 1e-300);
    Sparse I(A.rows(), A.cols());
    I.setIdentity();
    A += mu * I;
    Eigen::SimplicialLDLT<Sparse> ldlt(A);
    if (ldlt.info() != Eigen::Success)
      throw SolverError("assembled start: the joints' normal matrix G W^-1 G^T could not be factorised");
    const Eigen::VectorXd nu = ldlt.solve(r);
    return -(WGt * nu);
  }

  void move(const Eigen::VectorXd& dz, double step) {
    for (int i = 0; i < nb_; ++i) {
      if (held_[i]) continue;
      poses_[i].x += step * dz.segment<3>(6 * i);  // zero for a pivoted body (no translation columns)
      const Vec3 dtheta = step * dz.segment<3>(6 * i + 3);
      const double angle = dtheta.norm();
      if (angle > 0.0)
        poses_[i].R = so3::nearest_rotation(so3::axis_angle_to_matrix(dtheta / angle, angle) * poses_[i].R);
      if (pivots_[i].pivoted) poses_[i].x = pivots_[i].o + poses_[i].R * pivots_[i].c;
    }
  }

  [[noreturn]] void refuse(const Eigen::VectorXd& phi, const AssemblyReport& rep) const {
    int worst = 0;
    for (int r = 1; r < phi.size(); ++r)
      if (std::abs(phi(r)) * rows_[r].scale > std::abs(phi(worst)) * rows_[worst].scale) worst = r;
    const JointSpec& js = spec_.joints[rows_[worst].joint];
    std::string held;
    for (int b : rep.held) held += fmt::format("{}\"{}\"", held.empty() ? "" : ", ", spec_.bodies[b].name);
    const std::string where =
        js.where.file.empty() ? "" : fmt::format("{}:{}:{}: error: ", js.where.file, js.where.line, js.where.column);
    throw InputError(fmt::format(
        "{}joint '{}' ({}) row '{}': the mechanism cannot be assembled near the given poses: after {} Gauss-Newton "
        "steps the joint still misses by {:.3g} (start_tolerance {:g}; {:.3g} at the guess){}; the loop cannot "
        "close there: check the joint points and the link lengths, give guesses nearer the intended assembly, or "
        "hold fewer bodies{}",
        where, js.name, js.type->name, rows_[worst].row->name, rep.iterations,
        std::abs(phi(worst)) * rows_[worst].scale, spec_.start_tolerance, rep.initial_miss,
        held.empty() ? "" : fmt::format(", with {} held", held), pivot_hint()));
  }

  [[noreturn]] void refuse_velocities(const AssemblyReport& rep) const {
    std::string held;
    for (int b : rep.held) held += fmt::format("{}\"{}\"", held.empty() ? "" : ", ", spec_.bodies[b].name);
    const SourcePosition& w = spec_.assembly.where;
    throw InputError(fmt::format(
        "{}the held bodies' velocities cannot be kept: with {} as given, the least change of the other bodies' "
        "velocities still leaves the joints' velocity constraints off by {:.3g} (m/s or rad/s; {:.3g} before): the "
        "joints allow no such motion of the held bodies (check the mechanism's mobility and the held rates, or hold "
        "fewer bodies)",
        w.file.empty() ? "" : fmt::format("{}:{}:{}: error: ", w.file, w.line, w.column), held,
        rep.final_velocity_miss, rep.initial_velocity_miss));
  }

  // Pivoted bodies only turn about their pivots, keeping the lever their
  // guess gives: a guess whose position and orientation disagree gives a
  // wrong lever, and the loop cannot close with it.
  std::string pivot_hint() const {
    std::string names;
    int count = 0;
    for (int i = 0; i < nb_; ++i)
      if (pivots_[i].pivoted)
        names += fmt::format("{}\"{}\" (lever {:.4g} m)", count++ ? ", " : "", spec_.bodies[i].name,
                             pivots_[i].c.norm());
    if (count == 0) return "";
    return fmt::format("; {} only turn{} about {} pivot{}, with the lever from the pivot to the centre of mass that "
                       "the guess gives (R0^T (position - pivot)): check that each guessed position and orientation "
                       "agree",
                       names, count == 1 ? "s" : "", count == 1 ? "its" : "their", count == 1 ? "" : "s");
  }

  std::string describe(const AssemblyReport& rep) const {
    std::string held;
    for (int b : rep.held) held += fmt::format("{}{}", held.empty() ? "" : ", ", spec_.bodies[b].name);
    std::string moved;
    for (const AssembledBody& a : rep.bodies)
      if (!held_[a.body])
        moved += fmt::format("{}{} {:.3g} m, {:.3g} rad", moved.empty() ? "" : "; ", spec_.bodies[a.body].name,
                           a.moved_m, a.turned_rad);
    return fmt::format("assembled start ({}): {} Gauss-Newton steps, largest joint miss {:.3g} -> {:.3g}, velocity "
                       "miss {:.3g} -> {:.3g}; moved {}",
                       held.empty() ? "no body held" : "held " + held, rep.iterations, rep.initial_miss,
                       rep.final_miss, rep.initial_velocity_miss, rep.final_velocity_miss,
                       moved.empty() ? "nothing" : moved);
  }

  MultibodySpec& spec_;
  int nb_;
  double L_ = 0.0;
  std::vector<std::vector<ConstraintRow>> rows_of_joint_;
  std::vector<Row> rows_;
  std::vector<char> held_;
  std::vector<Pose> poses_;
  std::vector<PivotOf> pivots_;
};

}  // namespace

AssemblyReport assemble_start(MultibodySpec& spec) {
  if (!spec.assembly.requested) return {};
  return Assembler(spec).run();
}

}  // namespace rigidae::multibody
