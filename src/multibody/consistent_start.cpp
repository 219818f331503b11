// Consistent starts and projections of the multibody DAE (see
// multibody_problem.hpp): the joint misses, Gauss-Newton onto Phi = 0 with
// the least change in the mass metric, velocities onto G v = 0 (G v + Phi_t
// = 0 with drivers: their rows depend on time), the rank of
// G, and (v', lambda, mu, q') from the saddle-point system.
//
// With M the block-diagonal mass matrix (m I and the rotation block's M per
// body) and G the Force blocks' rows over all velocities:
//   position step:  [M G^T; G 0] (dv, nu) = (0, -Phi),      q += N(q) dv
//   velocities:     [M G^T; G 0] (dv, nu) = (0, -G v - Phi_t), v += dv
//   accelerations:  [M G^T; G 0] (v', lambda) = (f, target)
// (the least change in the mass metric, and the constrained accelerations),
// solved as one sparse saddle-point system: M may be singular.
// target = gamma for index3, index2, ggl (the true acceleration level) and
// the scheme's own row with v' = 0 otherwise (Baumgarte's feedback), so the
// residual vanishes. mu: (P P^T) mu = P q'_0 - rate, q' = q'_0 - P^T mu over
// the blocks with mu (P their Phi_q), rate 0, Baumgarte's -a Phi, or a
// driver's -Phi_t (so that Phi' = P q' + Phi_t = 0: mu = 0 once G v + Phi_t = 0).
// All sparse: O(bodies + joints) for chains.
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <Eigen/SPQRSupport>
#include <Eigen/OrderingMethods>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "rigidae/core/error.hpp"
#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/schemes/body_rows.hpp"

namespace rigidae::multibody {

namespace {

using Sparse = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;
using ConstMap = Eigen::Map<const Eigen::VectorXd>;

// Largest |x|, 0 for an empty vector.
double max_abs(const Eigen::VectorXd& x) { return x.size() ? x.cwiseAbs().maxCoeff() : 0.0; }

}  // namespace

void MultibodyProblem::constraint_matrices(Sparse& G, Eigen::VectorXd& phi, std::vector<int>* row_block,
                                           std::vector<int>* row_index) const {
  std::vector<Triplet> trip;
  std::vector<double> values;
  int row = 0;
  for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) {
    const ConstraintBlock& blk = blocks_[j];
    if (blk.kind != ConstraintKind::Force) continue;
    const BlockEval& e = block_eval_[j];
    for (int r = 0; r < blk.nr; ++r) {
      if (!blk.active[r]) continue;  // set aside: implied by the others
      for (int x = 0; x < 2; ++x) {
        const int bi = blk.body_of_side[x];
        if (bi == kGround) continue;
        for (int k = 0; k < e.G[x].cols(); ++k)
          if (e.G[x](r, k) != 0.0) trip.emplace_back(row, velocity_offset_[bi] + k, e.G[x](r, k));
      }
      values.push_back(e.phi(r));
      if (row_block) row_block->push_back(j);
      if (row_index) row_index->push_back(r);
      ++row;
    }
  }
  G.resize(row, nv_total_);
  G.setFromTriplets(trip.begin(), trip.end());
  phi = Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<int>(values.size()));
}

namespace {

// M as a sparse block-diagonal matrix.
Sparse mass_matrix(const std::vector<BodyModel>& bodies, const std::vector<int>& offsets,
                   const std::vector<Eigen::MatrixXd>& rot_mass, int nv) {
  std::vector<Triplet> trip;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const int o = offsets[i];
    const int nx = bodies[i].nx;
    for (int k = 0; k < nx; ++k) trip.emplace_back(o + k, o + k, bodies[i].mass);
    for (int r = 0; r < rot_mass[i].rows(); ++r)
      for (int c = 0; c < rot_mass[i].cols(); ++c) trip.emplace_back(o + nx + r, o + nx + c, rot_mass[i](r, c));
  }
  Sparse S(nv, nv);
  S.setFromTriplets(trip.begin(), trip.end());
  return S;
}

// Solves [M G^T; G 0] (x, z) = (r1, r2) by sparse LU. M itself may be
// singular where the constraints hold the motion (linear coordinates of a
// flat body, J1 = J2 + J3 about the centre of mass: E is singular), so no
// Schur complement through M^-1. Throws SolverError when the system is.
void solve_saddle(const Sparse& M, const Sparse& G, const Eigen::VectorXd& r1, const Eigen::VectorXd& r2,
                  Eigen::VectorXd& x, Eigen::VectorXd& z) {
  const int nv = static_cast<int>(M.rows()), nc = static_cast<int>(G.rows());
  std::vector<Triplet> trip;
  for (int k = 0; k < M.outerSize(); ++k)
    for (Sparse::InnerIterator it(M, k); it; ++it) trip.emplace_back(it.row(), it.col(), it.value());
  for (int k = 0; k < G.outerSize(); ++k)
    for (Sparse::InnerIterator it(G, k); it; ++it) {
      trip.emplace_back(nv + it.row(), it.col(), it.value());
      trip.emplace_back(it.col(), nv + it.row(), it.value());
    }
  Sparse K(nv + nc, nv + nc);
  K.setFromTriplets(trip.begin(), trip.end());
  K.makeCompressed();
  Eigen::SparseLU<Sparse, Eigen::COLAMDOrdering<int>> lu;
  lu.compute(K);
  if (lu.info() != Eigen::Success)
    throw SolverError("the constrained mass matrix [M G^T; G 0] is singular (dependent constraints or a body "
                      "without mass in some direction)");
  Eigen::VectorXd rhs(nv + nc);
  rhs << r1, r2;
  const Eigen::VectorXd sol = lu.solve(rhs);
  x = sol.head(nv);
  z = sol.tail(nc);
}

}  // namespace

void MultibodyProblem::project(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) {
  if (spec_.joints.empty()) {
    // Bodies not joined to one another: each body's own constraints only,
    // projected as the (deleted) one-body model did: q by the
    // representation's projection (unit quaternion, polar factor), then a
    // Force-kind body's v onto G v = 0 in its kinetic energy.
    for (const BodyModel& b : bodies_) {
      VecQ q = ConstMap(y.data() + groups_[b.q_group].offset + b.nx, b.nqr);
      b.rep->project_coordinates(q);
      y.segment(groups_[b.q_group].offset + b.nx, b.nqr) = q;
    }
    evaluate(t, y.data(), 2);
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      const BodyModel& b = bodies_[i];
      if (b.rep->nc() == 0 || b.rep->constraint_kind() != ConstraintKind::Force) continue;
      const int vo = groups_[b.v_group].offset + b.nx;
      VecV v = y.segment(vo, b.nvr);
      schemes::project_velocities(work_[i].terms, v);
      y.segment(vo, b.nvr) = v;
    }
    make_consistent(t, y, yp);
    return;
  }
  Sparse G;
  Eigen::VectorXd phi;
  std::vector<Eigen::MatrixXd> rot_mass(bodies_.size());
  const auto refresh = [&]() {
    evaluate(t, y.data(), 2);
    for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) evaluate_block(j, y.data(), nullptr);
    constraint_matrices(G, phi, nullptr, nullptr);
    for (std::size_t i = 0; i < bodies_.size(); ++i) rot_mass[i] = work_[i].terms.M;
  };
  // Positions: Gauss-Newton in the mass metric, internal constraints by the
  // representation's own projection (unit quaternion, polar factor).
  for (int it = 0; it < 30; ++it) {
    for (const BodyModel& b : bodies_) {
      VecQ q = ConstMap(y.data() + groups_[b.q_group].offset + b.nx, b.nqr);
      b.rep->project_coordinates(q);
      y.segment(groups_[b.q_group].offset + b.nx, b.nqr) = q;
    }
    refresh();
    if (max_abs(phi) < 1e-14) break;
    Eigen::VectorXd dv, nu;
    solve_saddle(mass_matrix(bodies_, velocity_offset_, rot_mass, nv_total_), G,
                 Eigen::VectorXd::Zero(nv_total_), -phi, dv, nu);
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      const BodyModel& b = bodies_[i];
      const int qo = groups_[b.q_group].offset, o = velocity_offset_[i];
      y.segment(qo, b.nx) += dv.segment(o, b.nx);
      const VecQ qr = y.segment(qo + b.nx, b.nqr);
      const VecV dvr = dv.segment(o + b.nx, b.nvr);
      StandardTerms terms;
      b.rep->evaluate(t, qr, dvr, terms);  // q' = N(q) v is linear in v
      y.segment(qo + b.nx, b.nqr) += terms.qdot;
    }
  }
  // Velocities onto G v = 0 in the mass metric.
  refresh();
  if (G.rows() > 0) {
    Eigen::VectorXd v(nv_total_);
    for (std::size_t i = 0; i < bodies_.size(); ++i)
      v.segment(velocity_offset_[i], groups_[bodies_[i].v_group].size) =
          y.segment(groups_[bodies_[i].v_group].offset, groups_[bodies_[i].v_group].size);
    Eigen::VectorXd dv, nu;
    // G v + Phi_t = 0: the blocks' velocity levels (a driver's carries Phi_t).
    Eigen::VectorXd rate(G.rows());
    int row = 0;
    for (int j = 0; j < static_cast<int>(blocks_.size()); ++j)
      if (blocks_[j].kind == ConstraintKind::Force)
        for (int r = 0; r < blocks_[j].nr; ++r)
          if (blocks_[j].active[r]) rate(row++) = block_eval_[j].Gv(r);  // G's rows: the active ones
    solve_saddle(mass_matrix(bodies_, velocity_offset_, rot_mass, nv_total_), G,
                 Eigen::VectorXd::Zero(nv_total_), -rate, dv, nu);
    v += dv;
    for (std::size_t i = 0; i < bodies_.size(); ++i)
      y.segment(groups_[bodies_[i].v_group].offset, groups_[bodies_[i].v_group].size) =
          v.segment(velocity_offset_[i], groups_[bodies_[i].v_group].size);
  }
  make_consistent(t, y, yp);
}

// Bodies not joined to one another (no joints, so no drivers): the saddle
// system [M G^T; G 0] is block diagonal, one block per body holding only the
// body's own constraints, i.e. the one-body model's system. Each body is
// made consistent by the one-body consistent start (schemes::
// consistent_start: dense, the same arithmetic as a one-body run), with f
// the body's generalized force as the residual at v' = 0 and no multipliers
// gives it (-F of its dynamic rows: the force elements' forces included);
// a translating body's x'' = f_x / m.
void MultibodyProblem::make_consistent_by_body(Eigen::VectorXd& y, Eigen::VectorXd& yp, const Eigen::VectorXd& F) {
  using BodyUnknowns = BoundedVec<kMaxCoordinates + kMaxVelocities + 2 * kMaxConstraints>;
  for (int i = 0; i < static_cast<int>(bodies_.size()); ++i) {
    const BodyModel& b = bodies_[i];
    const int qo = groups_[b.q_group].offset, vo = groups_[b.v_group].offset;
    for (int k = 0; k < b.nx; ++k) {
      yp(qo + k) = y(vo + k);
      yp(vo + k) = -F(vo + k) / b.mass;
    }
    if (b.nvr == 0) continue;  // a particle: no rotation block
    const ConstraintBlock* own = nullptr;
    for (const ConstraintBlock& blk : blocks_)
      if (blk.internal && blk.body == i) own = &blk;
    schemes::BodyLayout lay;
    lay.nq = b.nqr;
    lay.nv = b.nvr;
    if (own) {
      lay.n_lambda = own->lambda_group >= 0 ? own->nr : 0;
      lay.n_mu = own->mu_group >= 0 ? own->nr : 0;
      lay.kind = own->kind;
      lay.lambda_rows = own->lambda_rows;
      lay.mu_rows = own->mu_rows;
    }
    StandardTerms terms = work_[i].terms;  // at (q, v) of y: residual() evaluated them
    terms.f = -F.segment(vo + b.nx, b.nvr);
    BodyUnknowns u = BodyUnknowns::Zero(lay.size()), up = BodyUnknowns::Zero(lay.size());
    u.head(lay.nq) = y.segment(qo + b.nx, lay.nq);
    u.segment(lay.v_offset(), lay.nv) = y.segment(vo + b.nx, lay.nv);
    schemes::consistent_start(terms, lay, u, up);
    yp.segment(qo + b.nx, lay.nq) = up.head(lay.nq);
    yp.segment(vo + b.nx, lay.nv) = up.segment(lay.v_offset(), lay.nv);
    if (lay.n_lambda > 0) y.segment(groups_[own->lambda_group].offset, own->nr) = u.segment(lay.lambda_offset(), own->nr);
    if (lay.n_mu > 0) y.segment(groups_[own->mu_group].offset, own->nr) = u.segment(lay.mu_offset(), own->nr);
  }
}

void MultibodyProblem::make_consistent(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) {
  yp.setZero(n_);
  for (const ConstraintBlock& b : blocks_)
    for (int g : {b.lambda_group, b.mu_group})
      if (g >= 0) y.segment(groups_[g].offset, groups_[g].size).setZero();
  // With v' = 0 and no multipliers the dynamic rows are -f and the
  // constraint rows the scheme's rows without their v' part.
  Eigen::VectorXd F(n_);
  residual(t, y.data(), yp.data(), F.data());
  if (spec_.joints.empty()) {
    make_consistent_by_body(y, yp, F);
    return;
  }
  Sparse G;
  Eigen::VectorXd phi;
  constraint_matrices(G, phi, nullptr, nullptr);
  std::vector<Eigen::MatrixXd> rot_mass(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) rot_mass[i] = work_[i].terms.M;
  Eigen::VectorXd f(nv_total_);
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    f.segment(velocity_offset_[i], groups_[bodies_[i].v_group].size) =
        -F.segment(groups_[bodies_[i].v_group].offset, groups_[bodies_[i].v_group].size);
  // Targets of G v' per Force row.
  Eigen::VectorXd target(G.rows());
  int row = 0;
  for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) {
    const ConstraintBlock& blk = blocks_[j];
    if (blk.kind != ConstraintKind::Force) continue;
    for (int r = 0; r < blk.nr; ++r) {
      if (!blk.active[r]) continue;
      const double wa = blk.lambda_rows.acceleration;
      target(row++) = wa != 0.0 ? -F(groups_[blk.lambda_group].offset + r) / wa : -block_eval_[j].cacc(r);
    }
  }
  Eigen::VectorXd a, lambda;
  solve_saddle(mass_matrix(bodies_, velocity_offset_, rot_mass, nv_total_), G, f, target, a, lambda);
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    yp.segment(groups_[bodies_[i].v_group].offset, groups_[bodies_[i].v_group].size) =
        a.segment(velocity_offset_[i], groups_[bodies_[i].v_group].size);
  row = 0;
  for (const ConstraintBlock& blk : blocks_) {
    if (blk.kind != ConstraintKind::Force) continue;
    for (int r = 0; r < blk.nr; ++r)
      if (blk.active[r]) y(groups_[blk.lambda_group].offset + r) = lambda(row++);  // set aside: stays 0
  }
  // q'_0 = N v, then mu and q' = q'_0 - P^T mu.
  Eigen::VectorXd qdot = Eigen::VectorXd::Zero(n_);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const BodyModel& b = bodies_[i];
    const int qo = groups_[b.q_group].offset, vo = groups_[b.v_group].offset;
    qdot.segment(qo, b.nx) = y.segment(vo, b.nx);
    qdot.segment(qo + b.nx, b.nqr) = work_[i].terms.qdot;
  }
  std::vector<Triplet> trip;
  std::vector<double> rate;
  int nmu = 0;
  for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) {
    const ConstraintBlock& blk = blocks_[j];
    if (blk.mu_group < 0) continue;
    const BlockEval& e = block_eval_[j];
    for (int r = 0; r < blk.nr; ++r) {
      if (!blk.active[r]) continue;
      double Pq = 0.0;  // Phi_q q'_0 of the row
      for (int x = 0; x < 2; ++x) {
        const int bi = blk.body_of_side[x];
        if (bi == kGround) continue;
        const int qo = groups_[bodies_[bi].q_group].offset;
        for (int k = 0; k < e.phi_q[x].cols(); ++k)
          if (e.phi_q[x](r, k) != 0.0) {
            trip.emplace_back(nmu, qo + k, e.phi_q[x](r, k));
            Pq += e.phi_q[x](r, k) * qdot(qo + k);
          }
      }
      const LevelWeights& w = blk.mu_rows;
      if (blk.kind == ConstraintKind::Kinematic && w.velocity != 0.0)
        rate.push_back(-w.position * e.phi(r) / w.velocity);
      else if (blk.driver >= 0)
        // A driver's row moves with time: Phi' = Phi_q q' + Phi_t = 0 asks
        // P q' = -Phi_t = Phi_q q'_0 - (G v + Phi_t) (its velocity level, 0
        // after the projection), so mu = 0 as without drivers. With rate 0
        // mu held q' still and the first step met the driver's motion as an
        // inconsistency (IDA's error test failed at t0 for rtol <= 1e-11).
        rate.push_back(Pq - e.Gv(r));
      else
        rate.push_back(0.0);
      ++nmu;
    }
  }
  if (nmu > 0) {
    Sparse P(nmu, n_);
    P.setFromTriplets(trip.begin(), trip.end());
    const Sparse PPt = P * Sparse(P.transpose());
    Eigen::SimplicialLDLT<Sparse> ldlt(PPt);
    if (ldlt.info() != Eigen::Success) throw SolverError("the constraint matrix Phi_q Phi_q^T is singular");
    const Eigen::VectorXd mu =
        ldlt.solve(Eigen::VectorXd(P * qdot) - Eigen::Map<Eigen::VectorXd>(rate.data(), nmu));
    qdot -= Sparse(P.transpose()) * mu;
    int m = 0;
    for (const ConstraintBlock& blk : blocks_) {
      if (blk.mu_group < 0) continue;
      for (int r = 0; r < blk.nr; ++r)
        if (blk.active[r]) y(groups_[blk.mu_group].offset + r) = mu(m++);
    }
  }
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const int qo = groups_[bodies_[i].q_group].offset;
    yp.segment(qo, groups_[bodies_[i].q_group].size) = qdot.segment(qo, groups_[bodies_[i].q_group].size);
  }
}

// A driver's coordinate against f(t0) at the given poses (driver_scratch_
// filled by evaluate_block): refused beyond start_tolerance; for an angle
// the miss is theta - f wrapped (prescribed_miss), and f(t0) a whole number
// of turns from the pose is the same pose, said in a warning because the
// angle columns count from the pose's reading.
void MultibodyProblem::check_driver_start(int j, const std::string& where, double t0, double& worst,
                                          std::string& worst_row) {
  const DriverRow& d = drivers_[blocks_[j].driver];
  const double f = d.motion->value(t0);
  const bool angle = d.coordinate->kind != CoordinateKind::Length;
  // The coordinate as read at the given pose, its round-off shown as 0.
  const double raw = angle ? coordinate_angle(driver_scratch_) : driver_scratch_.phi(0);
  const double reading = std::abs(raw) < 1e-12 ? 0.0 : raw;
  const double miss = std::abs(prescribed_miss(d, driver_scratch_, t0));
  const char* unit = angle ? "rad" : "m";
  if (miss > spec_.start_tolerance)
    throw InputError(fmt::format("{}: the initial poses miss the prescribed motion by {:.3g} {} (more than "
                                 "start_tolerance {:g}): at t = {:g} the driver prescribes {:.6g} {}, the joint "
                                 "reads {:.6g} {}; place the bodies at that pose, or start the motion where they are",
                                 where, miss, unit, spec_.start_tolerance, t0, f, unit, reading, unit));
  if (angle) {
    const double turns = std::round((f - reading) / (2.0 * M_PI));
    if (turns != 0.0)
      warnings_.push_back(fmt::format(
          "{}: at t = {:g} the driver prescribes {:.6g} rad, {:g} whole turn{} from the pose's angle {:.6g} rad (the "
          "same pose): the joint's angle columns count from the pose, so they read the prescribed angle less {:g} "
          "rad",
          row_label(j, 0), t0, f, turns, std::abs(turns) == 1.0 ? "" : "s", reading,
          2.0 * M_PI * turns));
  }
  if (miss > worst) worst = miss, worst_row = row_label(j, 0);
}

void MultibodyProblem::start(const Scene& scene) {
  const double t0 = scene.time.start;
  bridge_.enabled = spec_.bridge_singular_poses;
  bridge_.t_end = scene.time.end;
  bridge_.rtol = scene.solver.rtol;
  bridge_.atol = scene.solver.atol;
  y0_.setZero(n_);
  physical_start(y0_);
  // A start error about one row, in the loaders' form "FILE:LINE:COL: error:
  // joint ..." when row_label put the joint's position in front.
  const auto row_error = [&](int block, int row) {
    std::string label = row_label(block, row);
    std::size_t joint = label.find("driver of joint '");
    if (joint == std::string::npos) joint = label.find("joint '");
    if (joint != std::string::npos && joint > 0) label.insert(joint, "error: ");
    return label;
  };
  // Joint misses at the given poses.
  evaluate(t0, y0_.data(), 2);
  double worst = 0.0;
  std::string worst_row;
  for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) {
    evaluate_block(j, y0_.data(), nullptr);
    if (blocks_[j].internal) continue;
    for (int r = 0; r < blocks_[j].nr; ++r) {
      if (!blocks_[j].active[r]) continue;  // set aside: checked below
      if (blocks_[j].driver >= 0) {
        check_driver_start(j, row_error(j, r), t0, worst, worst_row);
        continue;
      }
      const double miss = std::abs(block_eval_[j].phi(r));
      if (miss > spec_.start_tolerance)
        throw InputError(fmt::format("{}: the initial poses miss the joint by {:.3g} (more than start_tolerance "
                                     "{:g}); place the bodies so that the joint holds, or raise start_tolerance",
                                     row_error(j, r), miss, spec_.start_tolerance));
      if (miss > worst) worst = miss, worst_row = row_label(j, r);
    }
  }
  // Rows set aside as redundant (redundancy.cpp): a loop that cannot close
  // may show only in them.
  for (int k = 0; k < static_cast<int>(redundancy_.dropped.size()); ++k) {
    const RedundantRow& d = redundancy_.dropped[k];
    const JointSpec& js = spec_.joints[d.joint];
    const double miss = dropped_row_miss(k);
    if (miss > spec_.start_tolerance) {
      const std::string src = dropped_row_source(k);
      throw InputError(fmt::format("{}joint '{}' ({}) row '{}': the initial poses miss the joint by {:.3g} (more "
                                   "than start_tolerance {:g}); place the bodies so that the joint holds, or raise "
                                   "start_tolerance",
                                   src.empty() ? "" : src + ": error: ", js.name, js.type->name, d.row,
                                   miss, spec_.start_tolerance));
    }
  }
  Eigen::VectorXd v_before = y0_;
  project(t0, y0_, yp0_);
  check_redundant_rows(t0);
  if (worst > 1e-12)
    warnings_.push_back(fmt::format("{}: the initial poses missed the joint by {:.3g}; projected onto the joints",
                                    worst_row, worst));
  double dv = 0.0;
  int moved = -1;
  for (int i = 0; i < static_cast<int>(bodies_.size()); ++i) {
    const BodyModel& b = bodies_[i];
    const double d = (y0_.segment(groups_[b.v_group].offset, groups_[b.v_group].size) -
                      v_before.segment(groups_[b.v_group].offset, groups_[b.v_group].size))
                         .cwiseAbs()
                         .maxCoeff();
    if (d > dv) dv = d, moved = i;
  }
  if (dv > 1e-10) {
    const SourcePosition& w = spec_.bodies[moved].where;
    warnings_.push_back(fmt::format("{}body '{}': the initial velocities violated the joints; projected onto "
                                    "G v + Phi_t = 0 in the mass metric (largest change {:.3g}, on this body)",
                                    w.file.empty() ? "" : fmt::format("{}:{}:{}: ", w.file, w.line, w.column),
                                    bodies_[moved].name, dv));
  }
}

void MultibodyProblem::initial_state(double t0, Eigen::VectorXd& y, Eigen::VectorXd& yp) {
  y = y0_;
  yp = yp0_;
  events_.insert(events_.end(), start_events_.begin(), start_events_.end());
  // The start's subset of the rows (a run before this one may have chosen
  // another) and a fresh singular-pose watch.
  singular_poses_.clear();
  near_singular_ = false;
  start_condition_ = -1.0;
  branch_ = BranchWatch{};
  {
    PoseBridge fresh;
    fresh.enabled = bridge_.enabled;
    fresh.t_end = bridge_.t_end;
    fresh.rtol = bridge_.rtol;
    fresh.atol = bridge_.atol;
    bridge_ = std::move(fresh);
    // The start: the first node (only loops with rows set aside are watched).
    if (bridge_.enabled && watches_singular_poses()) bridge_after_step(t0, y, yp);
  }
  if (!redundancy_.dropped.empty()) {
    for (ConstraintBlock& b : blocks_)
      if (!b.internal) std::fill(b.active.begin(), b.active.end(), 1);
    for (const RedundantRow& d : redundancy_.dropped) blocks_[block_of_joint_[d.joint]].active[d.index] = 0;
    set_aside_ = redundancy_.dropped;
    subset_baseline_ = start_baseline_;
    subset_changes_ = 0;
    largest_dependency_ = 0.0;
    largest_amplification_ = 0.0;
  }
  // Force elements' own state (a torsion angle starts on its principal branch).
  for (const auto& f : forces_) f->reset();
  // Joint angles start on their principal branch (-pi, pi] too.
  for (CoordinateTrack& c : coordinates_) c.branch.reset();
  make_consistent(t0, y, yp);
  // The branches' first reference: the start's angles and rates at t0, from
  // which the first step's angles are predicted (multibody/angle_branch.hpp).
  follow_motion(t0, y.data());
}

std::pair<double, double> MultibodyProblem::projection_drift(double t, const double* y) {
  evaluate(t, y, 2, /*for_rows=*/true);
  double pos = 0.0, vel = 0.0;
  // Each body's own constraints, measured as the one-body model did
  // (schemes::block_drift), whether or not the scheme writes rows for them (the
  // projection scheme in the Euler form writes none: the plain ODE).
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const BodyModel& b = bodies_[i];
    if (b.rep->nc() == 0) continue;
    const VecV v = ConstMap(y + groups_[b.v_group].offset + b.nx, b.nvr);
    const schemes::BlockDrift d = schemes::block_drift(work_[i].terms, b.rep->constraint_kind(), v);
    pos = std::max(pos, d.position);
    vel = std::max(vel, d.velocity);
  }
  for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) {
    if (blocks_[j].internal) continue;
    evaluate_block(j, y, nullptr);
    pos = std::max(pos, block_eval_[j].phi.norm());
    vel = std::max(vel, block_eval_[j].Gv.norm());  // joints and drivers: Force blocks
  }
  const auto [dpos, dvel] = dropped_drift(y);  // rows set aside: each its own block
  return {std::max(pos, dpos), std::max(vel, dvel)};
}

std::pair<double, double> MultibodyProblem::drift(double t, const double* y) {
  // The accuracy monitor and the recorder both ask at every accepted step:
  // the second asks for the same (t, y) and gets the first's answer.
  if (drift_memo_valid_ && t == drift_memo_t_ && std::equal(y, y + n_, drift_memo_y_.data())) return drift_memo_;
  evaluate(t, y, 2, /*for_rows=*/true);
  double pos = 0.0, vel = 0.0;
  for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) {
    evaluate_block(j, y, nullptr);
    const BlockEval& e = block_eval_[j];
    pos = std::max(pos, max_abs(e.phi));
    if (blocks_[j].kind == ConstraintKind::Force) {
      vel = std::max(vel, max_abs(e.Gv));
    } else {
      const BodyWork& w = work_[blocks_[j].body];
      for (int r = 0; r < e.nr; ++r)
        vel = std::max(vel, std::abs(e.phi_q[0].row(r).tail(w.st.nqr).dot(w.terms.qdot)));
    }
  }
  const auto [dpos, dvel] = dropped_drift(y);  // implied by the kept rows: drift like them
  pos = std::max(pos, dpos);
  vel = std::max(vel, dvel);
  drift_memo_valid_ = true;
  drift_memo_t_ = t;
  std::copy(y, y + n_, drift_memo_y_.data());
  drift_memo_ = {pos, vel};
  return drift_memo_;
}

}  // namespace rigidae::multibody
