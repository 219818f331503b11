// The multibody DAE: construction, residual and exact iteration matrix
// (see multibody_problem.hpp for the equations).
#include <fmt/format.h>

#include "rigidae/multibody/multibody_problem.hpp"
#include "rigidae/core/text.hpp"

#include <algorithm>
#include <cmath>

#include "rigidae/core/error.hpp"
#include "rigidae/model/rigid_body.hpp"
#include "rigidae/multibody/point_mass.hpp"
#include "rigidae/schemes/body_rows.hpp"
#include "rigidae/so3/euler_sequence.hpp"

// Force elements: src/multibody/force_elements/ (the forces, their derivatives, potentials).

namespace rigidae::multibody {

namespace {

using ConstMap = Eigen::Map<const Eigen::VectorXd>;

// Baumgarte's default gains: the largest initial angular speed (at least 1/s),
// as for one body (scene.hpp, baumgarte_gains).
std::pair<double, double> gains(const Scene& scene, const MultibodySpec& spec) {
  double rate = 1.0;
  for (const BodySpec& b : spec.bodies) rate = std::max(rate, b.omega0_B.norm());
  return {scene.formulation.baumgarte.a.value_or(rate), scene.formulation.baumgarte.b.value_or(rate)};
}

}  // namespace

MultibodyProblem::MultibodyProblem(const Scene& scene) : spec_(*scene.multibody) {
  // An assembled start moves the guessed poses onto the joints first: the
  // rank analysis and everything after it see the assembled mechanism.
  assembly_ = assemble_start(spec_);
  const auto [ga, gb] = gains(scene, spec_);
  scheme_ = make_block_scheme(scene.formulation.scheme, ga, gb);
  switch_threshold_ = scene.formulation.euler.switch_threshold;
  switching_ = scene.formulation.euler.switching;
  projection_threshold_ = projection_threshold(scene);
  project_every_step_ = scene.formulation.projection.every_step;

  // One-body scenes for the rotation blocks: reference point at the centre
  // of mass, so no gravity torque and the inertia about the centre of mass.
  Scene base = scene;
  base.multibody.reset();
  base.support = Support::Free;
  base.body.com_B.setZero();
  base.gravity_W = spec_.gravity_W;
  int offset = 0;
  for (const BodySpec& bs : spec_.bodies) {
    Scene s = base;
    s.body.mass = bs.mass;
    s.body.inertia_com = bs.inertia_com;
    s.R0_WB = bs.R0_WB;
    s.omega0_B = bs.omega0_B;
    s.formulation.coordinates = bs.coordinates.value_or(scene.formulation.coordinates);
    BodyModel b;
    b.name = bs.name;
    b.particle = bs.particle;
    b.mass = bs.mass;
    b.inertia = bs.inertia_com;
    b.coordinates = s.formulation.coordinates;
    if (bs.particle) {
      b.rep = make_point_mass_rotation();
      b.map = make_fixed_rotation_map();
    } else {
      if (bs.pivot_W) pivot_body_scene(bs, s, b);  // the one-body model about the pivot (pivot.cpp)
      b.rep = make_representation(s, make_rigid_body_model(s));
      const so3::EulerSequence seq =
          b.rep->has_charts() ? so3::parse_euler_sequence(b.rep->chart_name(), false) : so3::EulerSequence{};
      b.map = make_rotation_map(b.coordinates, seq);
    }
    b.nqr = b.rep->nq();
    b.nvr = b.rep->nv();
    b.q_group = static_cast<int>(groups_.size());
    groups_.push_back({offset, b.nx + b.nqr});
    offset += b.nx + b.nqr;
    b.v_group = static_cast<int>(groups_.size());
    groups_.push_back({offset, b.nx + b.nvr});
    offset += b.nx + b.nvr;
    bodies_.push_back(std::move(b));
  }
  n_state_ = offset;
  nv_total_ = 0;
  for (const BodyModel& b : bodies_) {
    velocity_offset_.push_back(nv_total_);
    nv_total_ += b.nx + b.nvr;
  }

  work_.resize(bodies_.size());
  lagrange_form_ = scene.formulation.equations == Equations::Lagrange;
  for (int i = 0; i < static_cast<int>(bodies_.size()); ++i) {
    // A particle has no rotation velocities: the Lagrange branch of the body
    // vectors (loops over nqr = 0) is its exact kinematics in either form.
    work_[i].st.lagrange = lagrange_form_ || bodies_[i].particle;
    work_[i].st.nqr = bodies_[i].nqr;
    work_[i].st.nvr = bodies_[i].nvr;
    work_[i].st.nx = bodies_[i].nx;
    work_[i].st.pivot = bodies_[i].pivot;
    work_[i].st.lever = bodies_[i].lever;
  }
  choose_start_charts(scene.time.start);
  // The joints' rows, less those the rank analysis sets aside (redundant).
  std::vector<std::vector<ConstraintRow>> rows_of_joint;
  for (const JointSpec& js : spec_.joints) {
    rows_of_joint.emplace_back();
    js.type->rows(js, rows_of_joint.back());
  }
  drivers_of_joint_.assign(spec_.joints.size(), {});
  for (int d = 0; d < static_cast<int>(spec_.drivers.size()); ++d) {
    const DriverSpec& ds = spec_.drivers[d];
    const JointSpec& js = spec_.joints[ds.joint];
    DriverRow row;
    row.coordinate = &js.type->coordinates[ds.coordinate];
    row.coordinate->rows(js, row.rows);
    row.motion = &spec_.drivers[d].motion;
    drivers_.push_back(row);
    drivers_of_joint_[ds.joint].push_back(d);
  }
  find_redundant_rows(scene, rows_of_joint);
  if (spec_.expected_dof && *spec_.expected_dof != redundancy_.rank_dof) {
    const SourcePosition& w = spec_.expected_dof_where;
    redundancy_.mobility_warning = fmt::format(
        "{}expected_dof = {}, but the mechanism's mobility is {} (velocities {} minus the rank {} of the constraint "
        "rows; Gruebler-Kutzbach count {}, {})",
        w.file.empty() ? "" : fmt::format("{}:{}:{}: ", w.file, w.line, w.column), *spec_.expected_dof,
        redundancy_.rank_dof, redundancy_.velocities, redundancy_.rank, redundancy_.gruebler_dof,
        text::count(redundancy_.dropped.size(), "redundant row", "redundant rows"));
    warnings_.push_back(redundancy_.mobility_warning);
  }

  const auto add_groups = [&](ConstraintBlock& blk) {
    const KindRows& k = blk.kind == ConstraintKind::Force ? scheme_.force : scheme_.kinematic;
    blk.lambda_rows = k.lambda_rows;
    blk.mu_rows = k.mu_rows;
    if (k.lambda) {
      blk.lambda_group = static_cast<int>(groups_.size());
      groups_.push_back({offset, blk.nr});
      offset += blk.nr;
    }
    if (k.mu) {
      blk.mu_group = static_cast<int>(groups_.size());
      groups_.push_back({offset, blk.nr});
      offset += blk.nr;
    }
    if (blk.lambda_group >= 0 || blk.mu_group >= 0) blocks_.push_back(std::move(blk));
  };
  for (int i = 0; i < static_cast<int>(bodies_.size()); ++i) {
    const Representation& rep = *bodies_[i].rep;
    if (rep.nc() == 0) continue;
    ConstraintBlock blk;
    blk.internal = true;
    blk.body = i;
    blk.kind = rep.constraint_kind();
    blk.nr = rep.nc();
    blk.row_names = rep.constraint_names();
    blk.active.assign(blk.nr, 1);
    blk.body_of_side[0] = i;
    add_groups(blk);
  }
  for (int j = 0; j < static_cast<int>(spec_.joints.size()); ++j) {
    const JointSpec& js = spec_.joints[j];
    ConstraintBlock blk;
    blk.joint = j;
    blk.kind = ConstraintKind::Force;
    blk.rows = std::move(rows_of_joint[j]);
    blk.nr = static_cast<int>(blk.rows.size());
    if (blk.nr == 0) continue;
    blk.active.assign(blk.nr, 1);
    for (int k : dropped_of_joint_[j]) blk.active[redundancy_.dropped[k].index] = 0;
    for (const ConstraintRow& r : blk.rows) blk.row_names.push_back(r.name);
    blk.body_of_side[0] = js.body_a;
    blk.body_of_side[1] = js.body_b;
    has_force_blocks_ = true;
    add_groups(blk);
  }
  // Drivers: one rheonomic Force row each, after the joints.
  block_of_driver_.assign(spec_.drivers.size(), -1);
  for (int d = 0; d < static_cast<int>(spec_.drivers.size()); ++d) {
    const JointSpec& js = spec_.joints[spec_.drivers[d].joint];
    ConstraintBlock blk;
    blk.joint = spec_.drivers[d].joint;
    blk.driver = d;
    blk.kind = ConstraintKind::Force;
    blk.nr = 1;
    blk.active.assign(1, 1);  // a driver's row is never set aside
    blk.row_names.push_back("drive_" + std::string(drivers_[d].coordinate->name));
    blk.body_of_side[0] = js.body_a;
    blk.body_of_side[1] = js.body_b;
    block_of_driver_[d] = static_cast<int>(blocks_.size());
    add_groups(blk);
  }
  for (const ConstraintBlock& b : blocks_)
    if (b.kind == ConstraintKind::Force) has_force_blocks_ = true;
  // Per joint its block, looked up per output row (a search would make rows O(joints^2)).
  block_of_joint_.assign(spec_.joints.size(), -1);
  for (int k = 0; k < static_cast<int>(blocks_.size()); ++k)
    if (!blocks_[k].internal && blocks_[k].driver < 0) block_of_joint_[blocks_[k].joint] = k;
  n_ = offset;
  drift_memo_y_.resize(n_);

  block_eval_.resize(blocks_.size());
  // Every joint's coordinates (model/joint_type.hpp), joint by joint.
  for (int j = 0; j < static_cast<int>(spec_.joints.size()); ++j) {
    first_coordinate_.push_back(static_cast<int>(coordinates_.size()));
    for (const JointCoordinate& c : spec_.joints[j].type->coordinates) {
      CoordinateTrack t;
      t.joint = j;
      t.def = &c;
      c.rows(spec_.joints[j], t.rows);
      coordinates_.push_back(t);
    }
  }
  first_coordinate_.push_back(static_cast<int>(coordinates_.size()));
  forces_ = make_force_elements(spec_);
  for (const auto& f : forces_) forces_follow_motion_ = forces_follow_motion_ || f->follows_motion();
  force_bodies_.gravity_W = spec_.gravity_W;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    force_bodies_.state.push_back(&work_[i].st);
    force_bodies_.mass.push_back(bodies_[i].mass);
    force_bodies_.q_group.push_back(bodies_[i].q_group);
    force_bodies_.v_group.push_back(bodies_[i].v_group);
    force_bodies_.v_offset.push_back(groups_[bodies_[i].v_group].offset);
  }
  sink_ = std::make_unique<JacobianSink>(groups_);
  prepare_minimum_norm_reactions();
  decoupled_ = bodies_decoupled();

  start(scene);

  // The pattern: every (row group, column group) pair the assembly writes.
  sink_->start_recording();
  assemble_jacobian(scene.time.start, 1.0, y0_.data(), yp0_.data(), *sink_);
  for (const BodyModel& b : bodies_)
    for (int g : {b.q_group, b.v_group}) sink_->add_diagonal(g, 0.0);
  // A mechanism with rows set aside may set other joints' rows aside during
  // the run (row_subset.cpp): their rows lambda_r = 0 need the diagonal.
  if (!redundancy_.dropped.empty())
    for (const ConstraintBlock& b : blocks_)
      if (!b.internal)
        for (int g : {b.lambda_group, b.mu_group})
          if (g >= 0) sink_->add_diagonal(g, 0.0);
  pattern_ = sink_->finish_recording();
}

// As the (deleted) one-body model did at its start: a
// body whose Euler-angle chart is within the switching margin at its start
// pose starts in the most regular chart, its coordinates and velocities
// written there from the physical start (angle rates through the near-
// singular chart would be lost); without switching that is an error. Before
// the rank analysis, which then sees the start in the chart the run uses.
void MultibodyProblem::choose_start_charts(double t0) {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    BodyModel& b = bodies_[i];
    if (!b.rep->has_charts()) continue;
    const BodySpec& bs = spec_.bodies[i];
    VecQ q;
    VecV v;
    b.rep->from_physical(bs.R0_WB, bs.omega0_B, q, v);
    const double margin = b.rep->chart_margin(q);
    if (margin > switch_threshold_) continue;
    if (!switching_)
      throw InputError(fmt::format(
          "{}body '{}': the Euler-angle sequence '{}' is within its singularity margin at t = {} (margin {:.3g} <= "
          "switch_threshold {}); choose another sequence, 'auto', or enable switching",
          bs.where.file.empty() ? "" : fmt::format("{}:{}:{}: ", bs.where.file, bs.where.line, bs.where.column),
          b.name, b.rep->chart_name(), t0, margin, switch_threshold_));
    const int best = b.rep->most_regular_chart(q);
    if (best == b.rep->chart()) continue;
    EventNote note;
    note.t = t0;
    note.what = "chart_switch";
    note.body = b.name;
    note.from = b.rep->chart_name();
    note.margin = margin;
    b.rep = b.rep->in_chart(best);
    b.map->set_sequence(so3::parse_euler_sequence(b.rep->chart_name(), false));
    note.to = b.rep->chart_name();
    start_events_.push_back(note);
  }
}

void MultibodyProblem::evaluate(double t, const double* y, int order, bool for_rows) {
  evaluated_t_ = t;
  force_bodies_.t = t;
  // The placement R(q) and its partials serve joint rows, force elements and
  // reports; the residual and matrix of decoupled bodies (bodies_decoupled:
  // a one-body scene) read only the rotation block's terms.
  const bool placement = !for_rows || !decoupled_;
  placement_evaluated_ = placement;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const BodyModel& b = bodies_[i];
    BodyWork& w = work_[i];
    w.st.q = y + groups_[b.q_group].offset;
    w.st.v = y + groups_[b.v_group].offset;
    if (placement) b.map->evaluate(w.st.q + b.nx, order, w.st.P);
    const VecQ qr = ConstMap(w.st.q + b.nx, b.nqr);
    const VecV vr = ConstMap(w.st.v + b.nx, b.nvr);
    b.rep->evaluate(t, qr, vr, w.terms);
  }
}

void MultibodyProblem::evaluate_block(int j, const double* /*y*/, const double* /*yp*/) {
  const ConstraintBlock& blk = blocks_[j];
  BlockEval& e = block_eval_[j];
  if (!blk.internal) {
    BlockSides sides;
    for (int x = 0; x < 2; ++x) {
      sides.body[x] = blk.body_of_side[x];
      sides.state[x] = blk.body_of_side[x] == kGround ? nullptr : &work_[blk.body_of_side[x]].st;
    }
    if (blk.driver >= 0)
      evaluate_driver(drivers_[blk.driver], evaluated_t_, sides, driver_scratch_, e);
    else
      evaluate_rows(blk.rows.data(), blk.nr, sides, e);
    return;
  }
  const BodyWork& w = work_[blk.body];
  const int nr = blk.nr, nq = w.st.nq(), nv = w.st.nv();
  e.nr = nr;
  e.phi = w.terms.phi;
  e.phi_q[0].setZero(nr, nq);
  e.phi_q[0].rightCols(w.st.nqr) = w.terms.phi_q;
  e.G[0].setZero(nr, nv);
  e.Gv.setZero(nr);
  e.cacc.setZero(nr);
  if (blk.kind == ConstraintKind::Force) {
    e.G[0].rightCols(w.st.nvr) = w.terms.G;
    for (int k = 0; k < w.st.nvr; ++k) e.Gv += w.terms.G.col(k) * w.st.v[w.st.nx + k];
    e.cacc = -w.terms.gamma;
  }
  e.phi_q[1].resize(nr, 0);
  e.G[1].resize(nr, 0);
}

void MultibodyProblem::differentiate_block(int j, const double* y, const double* yp) {
  const ConstraintBlock& blk = blocks_[j];
  BlockEval& e = block_eval_[j];
  const double* lambda = blk.lambda_group >= 0 ? y + groups_[blk.lambda_group].offset : nullptr;
  const double* mu = blk.mu_group >= 0 ? y + groups_[blk.mu_group].offset : nullptr;
  if (!blk.internal) {
    BlockSides sides;
    const double* acc[2] = {nullptr, nullptr};
    for (int x = 0; x < 2; ++x) {
      const int b = blk.body_of_side[x];
      sides.body[x] = b;
      sides.state[x] = b == kGround ? nullptr : &work_[b].st;
      if (b != kGround) acc[x] = yp + groups_[bodies_[b].v_group].offset;
    }
    if (blk.driver >= 0)
      differentiate_driver(drivers_[blk.driver], evaluated_t_, sides, acc, lambda, mu, driver_scratch_, e);
    else
      differentiate_rows(blk.rows.data(), blk.nr, sides, acc, lambda, mu, e);
    return;
  }
  const BodyWork& w = work_[blk.body];
  const BodyModel& b = bodies_[blk.body];
  const int nr = blk.nr, nq = w.st.nq(), nv = w.st.nv(), nqr = b.nqr;
  const VecQ qr = ConstMap(w.st.q + b.nx, nqr);
  for (BlockMatQ* m : {&e.dGv_q[0], &e.dGa_q[0], &e.dc_q[0], &e.dPqp_q[0]}) m->setZero(nr, nq);
  e.dc_v[0].setZero(nr, nv);
  e.HL[0][0].setZero(nv, nq);
  e.HM[0][0].setZero(nq, nq);
  for (int x = 0; x < 2; ++x)
    for (int y2 = 0; y2 < 2; ++y2)
      if (x + y2 > 0) {
        e.HL[x][y2].resize(0, 0);
        e.HM[x][y2].resize(0, 0);
      }
  for (BlockMatQ* m : {&e.dGv_q[1], &e.dGa_q[1], &e.dc_q[1], &e.dPqp_q[1]}) m->resize(nr, 0);
  e.dc_v[1].resize(nr, 0);
  MatCQ H;
  MatQQ HH;
  if (blk.kind == ConstraintKind::Force) {
    const VecQ vr = ConstMap(w.st.v + b.nx, nqr);  // Lagrange form: v = q'
    const VecQ ar = ConstMap(yp + groups_[b.v_group].offset + b.nx, nqr);
    b.rep->constraint_hessian_applied(qr, vr, H);
    e.dGv_q[0].rightCols(nqr) = H;
    b.rep->constraint_hessian_applied(qr, ar, H);
    e.dGa_q[0].rightCols(nqr) = H;
    e.dc_q[0].rightCols(nqr) = -w.derivs.gamma_q;
    e.dc_v[0].rightCols(b.nvr) = -w.derivs.gamma_v;
    if (lambda) {
      const VecC l = ConstMap(lambda, nr);
      b.rep->constraint_hessian_weighted(qr, l, HH);
      e.HL[0][0].bottomRightCorner(nqr, nqr) = HH;
    }
  } else {
    const VecQ qp = ConstMap(yp + groups_[b.q_group].offset + b.nx, nqr);
    b.rep->constraint_hessian_applied(qr, qp, H);
    e.dPqp_q[0].rightCols(nqr) = H;
  }
  if (mu) {
    const VecC m = ConstMap(mu, nr);
    b.rep->constraint_hessian_weighted(qr, m, HH);
    e.HM[0][0].bottomRightCorner(nqr, nqr) = HH;
  }
}

// A body's own constraint block (the quaternion norm, R^T R = I) as the
// one-body model wrote it (body_rows.hpp): its multiplier rows from the
// body's terms, and G^T lambda, Phi_q^T mu added to its rotation rows.
void MultibodyProblem::internal_block_rows(const ConstraintBlock& blk, const Eigen::Map<const Eigen::VectorXd>& y,
                                           const Eigen::Map<const Eigen::VectorXd>& yp,
                                           Eigen::Map<Eigen::VectorXd>& F) const {
  const BodyModel& b = bodies_[blk.body];
  const StandardTerms& terms = work_[blk.body].terms;
  const int qr = groups_[b.q_group].offset + b.nx, vr = groups_[b.v_group].offset + b.nx;
  const auto v = y.segment(vr, b.nvr), qp = yp.segment(qr, b.nqr), vp = yp.segment(vr, b.nvr);
  if (blk.lambda_group >= 0) {
    const int lo = groups_[blk.lambda_group].offset;
    schemes::block_rows(terms, blk.kind, blk.lambda_rows, v, qp, vp, F.segment(lo, blk.nr));
    schemes::add_constraint_forces(terms, y.segment(lo, blk.nr), F.segment(vr, b.nvr));
  }
  if (blk.mu_group >= 0) {
    const int mo = groups_[blk.mu_group].offset;
    schemes::block_rows(terms, blk.kind, blk.mu_rows, v, qp, vp, F.segment(mo, blk.nr));
    schemes::add_kinematic_multipliers(terms, y.segment(mo, blk.nr), F.segment(qr, b.nqr));
  }
}

bool MultibodyProblem::residual(double t, const double* y, const double* yp, double* F) {
  for (BodyWork& w : work_) w.st.P.nq = 0;
  evaluate(t, y, lagrange_form_ ? 2 : 1, /*for_rows=*/true);
  const ConstMap ym(y, n_), ypm(yp, n_);
  Eigen::Map<Eigen::VectorXd> Fm(F, n_);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const BodyModel& b = bodies_[i];
    const BodyWork& w = work_[i];
    const int qo = groups_[b.q_group].offset, vo = groups_[b.v_group].offset;
    for (int k = 0; k < b.nx; ++k) {
      F[qo + k] = yp[qo + k] - y[vo + k];
      F[vo + k] = b.mass * yp[vo + k];
    }
    // The rotation block's rows in the deleted one-body model's order
    // (q' - N v; M v' formed first, then - f), as plain loops: Eigen's
    // product on these small blocks sums each row from its first column on,
    // as here, and its dispatch cost 1-2 % of a mechanism's residual
    // (callgrind). The single-body pins (tests/guard/pinned.json, recorded
    // from that model) hold the order bit for bit.
    const int qr = qo + b.nx, vr = vo + b.nx;
    for (int k = 0; k < b.nqr; ++k) F[qr + k] = yp[qr + k] - w.terms.qdot(k);
    for (int k = 0; k < b.nvr; ++k) {
      double s = 0.0;
      for (int l = 0; l < b.nvr; ++l) s += w.terms.M(k, l) * yp[vr + l];
      F[vr + k] = s - w.terms.f(k);
    }
  }
  for (const auto& f : forces_) f->add_force(force_bodies_, F);
  for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) {
    const ConstraintBlock& blk = blocks_[j];
    evaluate_block(j, y, yp);
    if (blk.internal) {
      internal_block_rows(blk, ym, ypm, Fm);
      continue;
    }
    const BlockEval& e = block_eval_[j];
    for (int r = 0; r < blk.nr; ++r) {
      double vel = e.Gv(r), ga = 0.0;
      if (blk.kind != ConstraintKind::Force) vel = 0.0;
      for (int x = 0; x < 2; ++x) {
        const int bi = blk.body_of_side[x];
        if (bi == kGround) continue;
        const BodyModel& b = bodies_[bi];
        const int qo = groups_[b.q_group].offset, vo = groups_[b.v_group].offset;
        for (int k = 0; k < e.G[x].cols(); ++k) ga += e.G[x](r, k) * yp[vo + k];
        if (blk.kind != ConstraintKind::Force)
          for (int k = 0; k < e.phi_q[x].cols(); ++k) vel += e.phi_q[x](r, k) * yp[qo + k];
      }
      const auto row = [&](const LevelWeights& w) {
        return w.position * e.phi(r) + w.velocity * vel + w.acceleration * (ga + e.cacc(r));
      };
      if (!blk.active[r]) {  // set aside: its multipliers are held at 0
        if (blk.lambda_group >= 0) F[groups_[blk.lambda_group].offset + r] = y[groups_[blk.lambda_group].offset + r];
        if (blk.mu_group >= 0) F[groups_[blk.mu_group].offset + r] = y[groups_[blk.mu_group].offset + r];
        continue;
      }
      if (blk.lambda_group >= 0) F[groups_[blk.lambda_group].offset + r] = row(blk.lambda_rows);
      if (blk.mu_group >= 0) F[groups_[blk.mu_group].offset + r] = row(blk.mu_rows);
    }
    for (int x = 0; x < 2; ++x) {
      const int bi = blk.body_of_side[x];
      if (bi == kGround) continue;
      const BodyModel& b = bodies_[bi];
      if (blk.lambda_group >= 0) {
        const double* l = y + groups_[blk.lambda_group].offset;
        const int vo = groups_[b.v_group].offset;
        for (int k = 0; k < e.G[x].cols(); ++k)
          for (int r = 0; r < blk.nr; ++r) F[vo + k] += e.G[x](r, k) * l[r];
      }
      if (blk.mu_group >= 0) {
        const double* m = y + groups_[blk.mu_group].offset;
        const int qo = groups_[b.q_group].offset;
        for (int k = 0; k < e.phi_q[x].cols(); ++k)
          for (int r = 0; r < blk.nr; ++r) F[qo + k] += e.phi_q[x](r, k) * m[r];
      }
    }
  }
  for (int i = 0; i < n_; ++i)
    if (!std::isfinite(F[i])) return false;
  return true;
}

void MultibodyProblem::assemble_jacobian(double t, double cj, const double* y, const double* yp,
                                         JacobianSink& sink) {
  const bool lagrange = lagrange_form_;
  evaluate(t, y, lagrange ? 3 : 2, /*for_rows=*/true);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const BodyModel& b = bodies_[i];
    BodyWork& w = work_[i];
    const int o = b.nx;
    const VecQ qr = ConstMap(w.st.q + o, b.nqr);
    const VecV vr = ConstMap(w.st.v + o, b.nvr);
    const VecV ar = ConstMap(yp + groups_[b.v_group].offset + o, b.nvr);
    b.rep->differentiate(t, qr, vr, ar, w.derivs);
    const int Q = b.q_group, V = b.v_group;
    sink.add_diagonal(Q, cj);
    sink.add(Q, Q, o, o, -w.derivs.qdot_q);
    if (o == 3) sink.add(Q, V, 0, 0, -Mat3::Identity());
    sink.add(Q, V, o, o, -w.derivs.N);
    sink.add(V, Q, o, o, w.derivs.Ma_q - w.derivs.f_q);
    if (o == 3) sink.add(V, V, 0, 0, (cj * b.mass) * Mat3::Identity());
    sink.add(V, V, o, o, cj * w.terms.M - w.derivs.f_v);
  }
  for (const auto& f : forces_) f->add_jacobian(force_bodies_, sink);
  BlockMatQ Aq;
  BlockMatV Av;
  for (int j = 0; j < static_cast<int>(blocks_.size()); ++j) {
    const ConstraintBlock& blk = blocks_[j];
    evaluate_block(j, y, yp);
    differentiate_block(j, y, yp);
    const BlockEval& e = block_eval_[j];
    const bool force = blk.kind == ConstraintKind::Force;
    for (int x = 0; x < 2; ++x) {
      const int bi = blk.body_of_side[x];
      if (bi == kGround) continue;
      const int Q = bodies_[bi].q_group, V = bodies_[bi].v_group;
      const auto rows = [&](int group, const LevelWeights& w) {
        if (group < 0) return;
        // Levels in the order the rows sum them (body_rows.hpp's block_rows):
        // acceleration, velocity, position.
        if (force)
          Aq = w.acceleration * (e.dGa_q[x] + e.dc_q[x]) + w.velocity * e.dGv_q[x] + w.position * e.phi_q[x];
        else
          Aq = w.acceleration * (e.dGa_q[x] + e.dc_q[x]) + (w.velocity * cj) * e.phi_q[x] +
               w.velocity * e.dPqp_q[x] + w.position * e.phi_q[x];
        for (int r = 0; r < blk.nr; ++r)
          if (!blk.active[r]) Aq.row(r).setZero();
        sink.add(group, Q, 0, 0, Aq);
        if ((force && w.velocity != 0.0) || w.acceleration != 0.0) {
          Av = w.acceleration * (cj * e.G[x] + e.dc_v[x]);
          if (force) Av += w.velocity * e.G[x];
          for (int r = 0; r < blk.nr; ++r)
            if (!blk.active[r]) Av.row(r).setZero();
          sink.add(group, V, 0, 0, Av);
        }
      };
      rows(blk.lambda_group, blk.lambda_rows);
      rows(blk.mu_group, blk.mu_rows);
      for (int y2 = 0; y2 < 2; ++y2) {
        const int by = blk.body_of_side[y2];
        if (by == kGround) continue;
        if (blk.lambda_group >= 0) sink.add(V, bodies_[by].q_group, 0, 0, e.HL[x][y2]);
        if (blk.mu_group >= 0) sink.add(Q, bodies_[by].q_group, 0, 0, e.HM[x][y2]);
      }
      if (blk.lambda_group >= 0) sink.add(V, blk.lambda_group, 0, 0, e.G[x].transpose());
      if (blk.mu_group >= 0) sink.add(Q, blk.mu_group, 0, 0, e.phi_q[x].transpose());
    }
    for (int r = 0; r < blk.nr; ++r)
      if (!blk.active[r])
        for (int g : {blk.lambda_group, blk.mu_group})
          if (g >= 0) sink.add(g, g, r, r, Eigen::Matrix<double, 1, 1>::Constant(1.0));
  }
}

void MultibodyProblem::iteration_matrix_dense(double t, double cj, const double* y, const double* yp, double* J) {
  std::fill(J, J + static_cast<std::size_t>(n_) * n_, 0.0);
  sink_->start_dense(J, n_);
  assemble_jacobian(t, cj, y, yp, *sink_);
}

void MultibodyProblem::iteration_matrix_sparse(double t, double cj, const double* y, const double* yp,
                                               double* values) {
  std::fill(values, values + pattern_.nnz(), 0.0);
  sink_->start_sparse(values);
  assemble_jacobian(t, cj, y, yp, *sink_);
}

void MultibodyProblem::differential_id(Eigen::Ref<Eigen::VectorXd> id) const {
  id.setZero();
  for (const BodyModel& b : bodies_) {
    id.segment(groups_[b.q_group].offset, groups_[b.q_group].size).setOnes();
    if (!(scheme_.index3 && has_force_blocks_))
      id.segment(groups_[b.v_group].offset, groups_[b.v_group].size).setOnes();
  }
}

// As for one body (ida_driver.cpp): the user's atol for q and v;
// multipliers max(atol, rtol^(3/4)) relative to their size at the start.
void MultibodyProblem::absolute_tolerances(double rtol, double atol, const Eigen::VectorXd& y0,
                                           Eigen::Ref<Eigen::VectorXd> out) const {
  out.setConstant(atol);
  double scale = 1.0;
  for (const ConstraintBlock& b : blocks_)
    for (int g : {b.lambda_group, b.mu_group})
      if (g >= 0) scale = std::max(scale, y0.segment(groups_[g].offset, groups_[g].size).cwiseAbs().maxCoeff());
  for (const ConstraintBlock& b : blocks_)
    for (int g : {b.lambda_group, b.mu_group})
      if (g >= 0) out.segment(groups_[g].offset, groups_[g].size).setConstant(std::max(atol, std::pow(rtol, 0.75)) * scale);
}

std::string MultibodyProblem::row_label(int block, int row) const {
  const ConstraintBlock& b = blocks_[block];
  if (b.internal) return "body '" + bodies_[b.body].name + "' constraint '" + b.row_names[row] + "'";
  const JointSpec& j = spec_.joints[b.joint];
  std::string where;
  if (b.driver >= 0) {
    const SourcePosition& w = spec_.drivers[b.driver].where;
    if (!w.file.empty() || w.line > 0) where = fmt::format("{}:{}:{}: ", w.file, w.line, w.column);
    return where + "driver of joint '" + j.name + "' (" + std::string(j.type->name) + ") row '" + b.row_names[row] + "'";
  }
  if (!j.where.file.empty() || j.where.line > 0)
    where = j.where.file + ":" + std::to_string(j.where.line) + ":" + std::to_string(j.where.column) + ": ";
  return where + "joint '" + j.name + "' (" + std::string(j.type->name) + ") row '" + b.row_names[row] + "'";
}

bool MultibodyProblem::bodies_decoupled() const {
  for (const ConstraintBlock& blk : blocks_)
    if (!blk.internal) return false;
  for (const BodyModel& b : bodies_)
    if (b.particle || !b.pivoted()) return false;
  for (const auto& f : forces_)
    if (f->acts_on_pivoted_bodies()) return false;
  return true;
}

}  // namespace rigidae::multibody
