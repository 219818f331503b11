// Per-body and per-joint quantities for the recorder: orientation, angular
// velocity, centre-of-mass motion, joint reactions and residuals, energy and
// momentum. Not the hot path.
//
// Joint reactions from the multipliers, on body b at its joint point p_b, in
// space: a coincident-points row k carries the force lambda_k e_k on b; a
// point-on-line row with normal n (fixed in a) the force -lambda n on b; a
// perpendicular pair d_a . d_b the torque lambda (d_a x d_b) on b. When b is
// the ground the reaction on a is reported (the negatives, moved to p_a).
//
// Joint coordinates (model/joint_type.hpp): an angle is atan2(S, C) of its
// two rows, on the branch nearest the value at the last accepted step (so a
// crank that turns counts whole turns: the unwrapping holds while a joint
// turns less than half a turn per step), its rate (C S' - S C') / (C^2 +
// S^2); a length is its row's value, its rate G v.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "rigidae/multibody/multibody_problem.hpp"

#include <span>
#include "rigidae/so3/rotation.hpp"

namespace rigidae::multibody {

namespace {
using ConstMap = Eigen::Map<const Eigen::VectorXd>;
}

Vec4 MultibodyProblem::body_orientation(int i, const double* y) const {
  const BodyModel& b = bodies_[i];
  return b.rep->orientation(ConstMap(y + groups_[b.q_group].offset + b.nx, b.nqr));
}

Vec3 MultibodyProblem::body_omega_space(int i, const double* y) const {
  const BodyModel& b = bodies_[i];
  const VecQ q = ConstMap(y + groups_[b.q_group].offset + b.nx, b.nqr);
  const VecV v = ConstMap(y + groups_[b.v_group].offset + b.nx, b.nvr);
  const Vec4 qu = b.rep->orientation(q);
  return so3::quaternion_to_matrix(qu) * b.rep->body_angular_velocity(q, v);
}

Vec3 MultibodyProblem::body_position(int i, const double* y) const {
  const BodyModel& b = bodies_[i];
  if (b.pivoted()) return b.pivot + so3::quaternion_to_matrix(body_orientation(i, y)) * b.lever;
  return ConstMap(y + groups_[b.q_group].offset, 3);
}

Vec3 MultibodyProblem::body_velocity(int i, const double* y) const {
  const BodyModel& b = bodies_[i];
  if (b.pivoted())  // omega x (R c)
    return body_omega_space(i, y).cross(so3::quaternion_to_matrix(body_orientation(i, y)) * b.lever);
  return ConstMap(y + groups_[b.v_group].offset, 3);
}

JointReaction MultibodyProblem::joint_reaction(int joint, const double* y) {
  // A joint in a redundant loop's dependency: the minimum-norm split
  // (minimum_norm_reactions.cpp); else its own multipliers.
  if (minimum_norm_applies(joint)) return minimum_norm_reaction(joint, y);
  const int j = block_of_joint_[joint];
  if (j < 0 || blocks_[j].lambda_group < 0) return {};
  if (y != evaluated_y_) evaluate(0.0, y, 2);
  const ConstraintBlock& blk = blocks_[j];
  const ConstraintRow* rows[kMaxBlockRows];
  for (int r = 0; r < blk.nr; ++r) rows[r] = &blk.rows[r];
  return reaction_of_rows(joint, rows, y + groups_[blk.lambda_group].offset, blk.nr);
}

JointReaction MultibodyProblem::reaction_of_rows(int joint, const ConstraintRow* const* rows, const double* lambda,
                                                 int count) {
  JointReaction out;
  const JointSpec& js = spec_.joints[joint];
  VectorEval e[2];
  Vec3 pa = js.point_a, pb = js.point_b;
  if (js.body_a != kGround) {
    evaluate_vector(work_[js.body_a].st, {js.body_a, js.point_a, true}, e[0]);
    pa = e[0].value;
  }
  if (js.body_b != kGround) {
    evaluate_vector(work_[js.body_b].st, {js.body_b, js.point_b, true}, e[1]);
    pb = e[1].value;
  }
  VectorEval ta, tb;
  // What each multiplier is, the row states (model/constraint_row.hpp).
  for (int r = 0; r < count; ++r) {
    const ConstraintRow& row = *rows[r];
    switch (row.reaction) {
      case RowReaction::Point:  // p_a . e_k - p_b . e_k
        out.force += lambda[r] * row.terms[0].b.s;
        break;
      case RowReaction::Line: {  // p_b . n - p_a . n, n fixed in a
        const BodyVector& n = row.terms[0].b;
        Vec3 nw = n.s;
        if (n.body != kGround) {
          evaluate_vector(work_[n.body].st, n, ta);
          nw = ta.value;
        }
        out.force -= lambda[r] * nw;
        break;
      }
      case RowReaction::Turn: {  // d_a . d_b
        const DotTerm& t = row.terms[0];
        Vec3 da = t.a.s, db = t.b.s;
        if (t.a.body != kGround) evaluate_vector(work_[t.a.body].st, t.a, ta), da = ta.value;
        if (t.b.body != kGround) evaluate_vector(work_[t.b.body].st, t.b, tb), db = tb.value;
        out.torque += lambda[r] * da.cross(db);
        break;
      }
      case RowReaction::Distance:  // (|p_b - p_a|^2 - L^2) / (2L): the tension along the rod
        out.force -= lambda[r] * (pb - pa) / js.length;
        break;
      case RowReaction::Coordinate: break;  // not a constraint row
    }
  }
  // A point-on-line force acts at p_b; on a it acts at p_b too, so moved to p_a
  // it adds (p_b - p_a) x F.
  if (js.body_b == kGround) {
    out.torque = -out.torque - (pb - pa).cross(out.force);
    out.force = -out.force;
  }
  return out;
}

std::pair<double, double> MultibodyProblem::joint_residuals(int joint, const double* y) {
  const int j = block_of_joint_[joint];
  if (j < 0) return {0.0, 0.0};
  if (y != evaluated_y_) evaluate(0.0, y, 2);
  // Every row of the joint, those set aside included (they stay in the block).
  evaluate_block(j, y, nullptr);
  return {block_eval_[j].phi.norm(), block_eval_[j].Gv.norm()};
}

double MultibodyProblem::kinetic_energy(const double* y) const {
  double T = 0.0;
  for (int i = 0; i < static_cast<int>(bodies_.size()); ++i) {
    const BodyModel& b = bodies_[i];
    const VecQ q = ConstMap(y + groups_[b.q_group].offset + b.nx, b.nqr);
    const VecV v = ConstMap(y + groups_[b.v_group].offset + b.nx, b.nvr);
    const Vec3 w = b.rep->body_angular_velocity(q, v);
    T += 0.5 * b.mass * body_velocity(i, y).squaredNorm() + 0.5 * w.dot(b.inertia * w);
  }
  return T;
}

// The force elements' potentials: the fields' (gravity, constant space
// forces) summed first, then the elastic ones.
double MultibodyProblem::potential_energy(const double* y) {
  if (y != evaluated_y_) evaluate(0.0, y, 2);
  const double* keep = evaluated_y_;
  evaluated_y_ = y;
  double V = 0.0;
  for (const auto& f : forces_)
    if (!f->elastic()) V += f->potential_energy(force_bodies_);
  V += elastic_energy(y);
  evaluated_y_ = keep;
  return V;
}

double MultibodyProblem::elastic_energy(const double* y) {
  if (y != evaluated_y_) evaluate(0.0, y, 2);
  double V = 0.0;
  for (const auto& f : forces_)
    if (f->elastic()) V += f->potential_energy(force_bodies_);
  return V;
}

bool MultibodyProblem::conserves_energy() const {
  for (const auto& f : forces_)
    if (!f->conservative()) return false;
  return true;
}

bool MultibodyProblem::energy_balance_known() const {
  for (const auto& f : forces_)
    if (!f->conservative() && !f->has_power()) return false;
  return true;
}

int MultibodyProblem::joint_coordinate_count(int joint) const {
  return first_coordinate_[joint + 1] - first_coordinate_[joint];
}

void MultibodyProblem::coordinate_value(const CoordinateTrack& c, double& value, double& rate) {
  const JointSpec& js = spec_.joints[c.joint];
  BlockSides sides;
  sides.body[0] = js.body_a;
  sides.body[1] = js.body_b;
  for (int x = 0; x < 2; ++x) sides.state[x] = sides.body[x] == kGround ? nullptr : &work_[sides.body[x]].st;
  evaluate_rows(c.rows, c.def->row_count(), sides, coordinate_eval_);
  const BlockEval& e = coordinate_eval_;
  if (c.def->kind == CoordinateKind::Length) {
    value = e.phi(0);
    rate = e.Gv(0);
    return;
  }
  const double C = e.phi(0), S = e.phi(1);
  rate = (C * e.Gv(1) - S * e.Gv(0)) / (C * C + S * S);
  value = c.branch.continued(std::atan2(S, C), rate, evaluated_t_);
}

void MultibodyProblem::joint_coordinates(int joint, const double* y, double* value, double* rate) {
  if (y != evaluated_y_) evaluate(0.0, y, 2);
  for (int k = first_coordinate_[joint]; k < first_coordinate_[joint + 1]; ++k)
    coordinate_value(coordinates_[k], value[k - first_coordinate_[joint]], rate[k - first_coordinate_[joint]]);
}

Vec3 MultibodyProblem::linear_momentum(const double* y) const {
  Vec3 P = Vec3::Zero();
  for (int i = 0; i < static_cast<int>(bodies_.size()); ++i) P += bodies_[i].mass * body_velocity(i, y);
  return P;
}

Vec3 MultibodyProblem::angular_momentum(const double* y) const {
  Vec3 L = Vec3::Zero();
  for (int i = 0; i < static_cast<int>(bodies_.size()); ++i) {
    const BodyModel& b = bodies_[i];
    const VecQ q = ConstMap(y + groups_[b.q_group].offset + b.nx, b.nqr);
    const VecV v = ConstMap(y + groups_[b.v_group].offset + b.nx, b.nvr);
    const Mat3 R = so3::quaternion_to_matrix(b.rep->orientation(q));
    L += body_position(i, y).cross(b.mass * body_velocity(i, y)) + R * (b.inertia * b.rep->body_angular_velocity(q, v));
  }
  return L;
}

}  // namespace rigidae::multibody

namespace rigidae::multibody {

namespace {

RecordedParts every_part(std::size_t bodies, std::size_t joints) {
  RecordedParts p;
  for (std::size_t i = 0; i < bodies; ++i) p.bodies.push_back(static_cast<int>(i));
  for (std::size_t j = 0; j < joints; ++j) p.joints.push_back(static_cast<int>(j));
  return p;
}

constexpr const char* kBodyColumns[] = {"qw", "qx", "qy", "qz", "wx", "wy", "wz", "x", "y", "z", "vx", "vy", "vz"};
constexpr const char* kBodyUnits[] = {"1", "1", "1", "1", "rad/s", "rad/s", "rad/s", "m", "m", "m", "m/s", "m/s", "m/s"};
// A particle has no orientation: only its position and velocity columns.
constexpr int kRotationColumns = 7;
std::span<const char* const> body_columns(const BodyModel& b) {
  return std::span<const char* const>(kBodyColumns).subspan(b.particle ? kRotationColumns : 0);
}
std::span<const char* const> body_units(const BodyModel& b) {
  return std::span<const char* const>(kBodyUnits).subspan(b.particle ? kRotationColumns : 0);
}
// A joint's reaction and the residuals of its rows (|Phi|, |G v|: m for
// point rows, 1 for angular ones), then its coordinates (joint_coordinate_columns).
constexpr const char* kJointColumns[] = {"force_x",  "force_y",  "force_z",           "torque_x",
                                         "torque_y", "torque_z", "residual_position", "residual_velocity"};
constexpr const char* kJointUnits[] = {"N", "N", "N", "N m", "N m", "N m", "m|1", "m/s|1/s"};

// JOINT.<coordinate> and JOINT.<coordinate>_rate per coordinate of the
// joint's type, then per driver of the joint its driving torque
// JOINT.drive_torque (N m) or force JOINT.drive_force (N), named
// JOINT.<coordinate>_drive_torque when the type has two coordinates of that
// kind (a universal joint's two angles).
void joint_coordinate_columns(const MultibodySpec& spec, const std::vector<int>& drivers, int joint,
                              std::vector<std::string>& names, std::vector<std::string>& units) {
  const JointSpec& j = spec.joints[joint];
  for (const JointCoordinate& c : j.type->coordinates) {
    const bool angle = c.kind == CoordinateKind::Angle;
    names.push_back(j.name + "." + std::string(c.name));
    names.push_back(j.name + "." + std::string(c.name) + "_rate");
    units.push_back(angle ? "rad" : "m");
    units.push_back(angle ? "rad/s" : "m/s");
  }
  for (int d : drivers) {
    const JointCoordinate& c = j.type->coordinates[spec.drivers[d].coordinate];
    const bool angle = c.kind == CoordinateKind::Angle;
    const auto same_kind = std::count_if(j.type->coordinates.begin(), j.type->coordinates.end(),
                                         [&](const JointCoordinate& o) { return o.kind == c.kind; });
    const std::string effort = angle ? "drive_torque" : "drive_force";
    names.push_back(j.name + "." + (same_kind > 1 ? std::string(c.name) + "_" : std::string()) + effort);
    units.push_back(angle ? "N m" : "N");
  }
}
// A marker's position, velocity and acceleration in space (markers.cpp).
constexpr const char* kMarkerColumns[] = {"x", "y", "z", "vx", "vy", "vz", "ax", "ay", "az"};
constexpr const char* kMarkerUnits[] = {"m", "m", "m", "m/s", "m/s", "m/s", "m/s^2", "m/s^2", "m/s^2"};
// A pivoted body's support force (space, on the body at its pivot), after its body columns.
constexpr const char* kPivotColumns[] = {"pivot_force_x", "pivot_force_y", "pivot_force_z"};
constexpr const char* kPivotUnits[] = {"N", "N", "N"};
constexpr const char* kGlobalColumns[] = {"energy", "p_x", "p_y", "p_z", "L_x", "L_y", "L_z"};
constexpr const char* kGlobalUnits[] = {"J", "N s", "N s", "N s", "N m s", "N m s", "N m s"};

}  // namespace

std::vector<std::string> MultibodyProblem::output_names() const {
  return output_names(every_part(bodies_.size(), spec_.joints.size()));
}

std::vector<std::string> MultibodyProblem::output_units() const {
  return output_units(every_part(bodies_.size(), spec_.joints.size()));
}

void MultibodyProblem::output_row(double t, const double* y, double* out) {
  output_row(t, y, every_part(bodies_.size(), spec_.joints.size()), out);
}

std::vector<std::string> MultibodyProblem::output_names(const RecordedParts& parts) const {
  std::vector<std::string> n;
  for (int i : parts.bodies) {
    for (const char* c : body_columns(bodies_[i])) n.push_back(bodies_[i].name + "." + c);
    if (bodies_[i].pivoted())
      for (const char* c : kPivotColumns) n.push_back(bodies_[i].name + "." + c);
  }
  std::vector<std::string> units;
  for (int j : parts.joints) {
    for (const char* c : kJointColumns) n.push_back(spec_.joints[j].name + "." + c);
    joint_coordinate_columns(spec_, drivers_of_joint_[j], j, n, units);
  }
  for (const MarkerSpec& m : spec_.markers)
    for (const char* c : kMarkerColumns) n.push_back(m.name + "." + c);
  for (const char* c : kGlobalColumns) n.push_back(c);
  return n;
}

std::vector<std::string> MultibodyProblem::output_units(const RecordedParts& parts) const {
  std::vector<std::string> u;
  for (int i : parts.bodies) {
    const auto units = body_units(bodies_[i]);
    u.insert(u.end(), units.begin(), units.end());
    if (bodies_[i].pivoted()) u.insert(u.end(), std::begin(kPivotUnits), std::end(kPivotUnits));
  }
  std::vector<std::string> names;
  for (int j : parts.joints) {
    u.insert(u.end(), std::begin(kJointUnits), std::end(kJointUnits));
    joint_coordinate_columns(spec_, drivers_of_joint_[j], j, names, u);
  }
  for (std::size_t m = 0; m < spec_.markers.size(); ++m) u.insert(u.end(), std::begin(kMarkerUnits), std::end(kMarkerUnits));
  u.insert(u.end(), std::begin(kGlobalUnits), std::end(kGlobalUnits));
  return u;
}

void MultibodyProblem::output_row(double t, const double* y, const RecordedParts& parts, double* out) {
  // The support forces first (each evaluates the system itself), then one
  // evaluation of every body serves all joints (O(bodies + joints)).
  int k = 0;
  for (int i : parts.bodies) {
    k += static_cast<int>(std::size(kBodyColumns));
    if (bodies_[i].pivoted()) {
      const Vec3 f = support_force(i, y);
      for (int c = 0; c < 3; ++c) out[k++] = f(c);
    }
  }
  evaluate(t, y, 2);
  evaluated_y_ = y;
  k = 0;
  for (int i : parts.bodies) {
    const Vec4 q = body_orientation(i, y);
    const Vec3 w = body_omega_space(i, y), x = body_position(i, y), v = body_velocity(i, y);
    if (!bodies_[i].particle) {
      for (int c = 0; c < 4; ++c) out[k++] = q(c);
      for (int c = 0; c < 3; ++c) out[k++] = w(c);
    }
    for (const Vec3* a : {&x, &v})
      for (int c = 0; c < 3; ++c) out[k++] = (*a)(c);
    if (bodies_[i].pivoted()) k += 3;
  }
  for (int j : parts.joints) {
    const JointReaction r = joint_reaction(j, y);
    const auto [phi, phidot] = joint_residuals(j, y);
    for (const Vec3* a : {&r.force, &r.torque})
      for (int c = 0; c < 3; ++c) out[k++] = (*a)(c);
    out[k++] = phi;
    out[k++] = phidot;
    k += write_coordinates(j, y, out + k);
  }
  if (!spec_.markers.empty()) {
    marker_kinematics(t, y, out + k);
    k += 9 * static_cast<int>(spec_.markers.size());
    evaluate(t, y, 2);
  }
  out[k++] = kinetic_energy(y) + potential_energy(y);
  const Vec3 p = linear_momentum(y), L = angular_momentum(y);
  for (const Vec3* a : {&p, &L})
    for (int c = 0; c < 3; ++c) out[k++] = (*a)(c);
  evaluated_y_ = nullptr;
}

// --- Per-step rows. A body's own block (internal blocks come first, in body
// order) and a joint's block carry lambda and/or mu as the scheme's rows()
// say; a joint without multipliers has none of these columns.

namespace {

// Walks the internal blocks alongside the chosen bodies (both in body order):
// calls f(block index) for each chosen body that has one.
template <typename F>
void for_chosen_internal_blocks(const std::vector<ConstraintBlock>& blocks, const std::vector<int>& bodies, F f) {
  std::size_t k = 0;
  for (int j = 0; j < static_cast<int>(blocks.size()) && blocks[j].internal; ++j) {
    while (k < bodies.size() && bodies[k] < blocks[j].body) ++k;
    if (k < bodies.size() && bodies[k] == blocks[j].body) f(j);
  }
}

}  // namespace

std::vector<std::string> MultibodyProblem::step_part_names(const RecordedParts& parts) const {
  std::vector<std::string> n;
  const auto multipliers = [&](const ConstraintBlock& b, const std::string& owner) {
    if (b.lambda_group >= 0)
      for (const std::string& r : b.row_names) n.push_back(owner + ".lambda_" + r);
    if (b.mu_group >= 0)
      for (const std::string& r : b.row_names) n.push_back(owner + ".mu_" + r);
  };
  for_chosen_internal_blocks(blocks_, parts.bodies, [&](int j) { multipliers(blocks_[j], bodies_[blocks_[j].body].name); });
  for (int i : parts.bodies)
    if (bodies_[i].pivoted())
      for (const char* c : kPivotColumns) n.push_back(bodies_[i].name + "." + c);
  for (int joint : parts.joints) {
    const std::string& name = spec_.joints[joint].name;
    if (block_of_joint_[joint] >= 0) multipliers(blocks_[block_of_joint_[joint]], name);
    for (const char* c : kJointColumns) n.push_back(name + "." + c);
    std::vector<std::string> units;
    joint_coordinate_columns(spec_, drivers_of_joint_[joint], joint, n, units);
  }
  for (const MarkerSpec& m : spec_.markers)
    for (const char* c : kMarkerColumns) n.push_back(m.name + "." + c);
  return n;
}

std::vector<std::string> MultibodyProblem::step_part_units(const RecordedParts& parts) const {
  std::vector<std::string> u;
  const auto multipliers = [&](const ConstraintBlock& b, const char* lambda, const char* mu) {
    if (b.lambda_group >= 0) u.insert(u.end(), b.row_names.size(), lambda);
    if (b.mu_group >= 0) u.insert(u.end(), b.row_names.size(), mu);
  };
  for_chosen_internal_blocks(blocks_, parts.bodies, [&](int j) { multipliers(blocks_[j], "J", "1/s"); });
  for (int i : parts.bodies)
    if (bodies_[i].pivoted()) u.insert(u.end(), std::begin(kPivotUnits), std::end(kPivotUnits));
  for (int joint : parts.joints) {
    if (block_of_joint_[joint] >= 0) multipliers(blocks_[block_of_joint_[joint]], "N|N m", "m/s|1/s");
    u.insert(u.end(), std::begin(kJointUnits), std::end(kJointUnits));
    std::vector<std::string> names;
    joint_coordinate_columns(spec_, drivers_of_joint_[joint], joint, names, u);
  }
  for (std::size_t m = 0; m < spec_.markers.size(); ++m) u.insert(u.end(), std::begin(kMarkerUnits), std::end(kMarkerUnits));
  return u;
}

void MultibodyProblem::step_part_row(double t, const double* y, const RecordedParts& parts, double* out) {
  int k = 0;
  const auto multipliers = [&](const ConstraintBlock& b) {
    for (int g : {b.lambda_group, b.mu_group})
      if (g >= 0)
        for (int r = 0; r < b.nr; ++r) out[k++] = y[groups_[g].offset + r];
  };
  for_chosen_internal_blocks(blocks_, parts.bodies, [&](int j) { multipliers(blocks_[j]); });
  for (int i : parts.bodies)
    if (bodies_[i].pivoted()) {
      const Vec3 f = support_force(i, y);  // evaluates the system itself
      for (int c = 0; c < 3; ++c) out[k++] = f(c);
    }
  evaluate(t, y, 2);
  evaluated_y_ = y;
  for (int joint : parts.joints) {
    if (block_of_joint_[joint] >= 0) multipliers(blocks_[block_of_joint_[joint]]);
    const JointReaction r = joint_reaction(joint, y);
    const auto [phi, phidot] = joint_residuals(joint, y);
    for (const Vec3* a : {&r.force, &r.torque})
      for (int c = 0; c < 3; ++c) out[k++] = (*a)(c);
    out[k++] = phi;
    out[k++] = phidot;
    k += write_coordinates(joint, y, out + k);
  }
  marker_kinematics(t, y, out + k);
  evaluated_y_ = nullptr;
}

// Value, rate per coordinate of the joint (as the column names pair them).
int MultibodyProblem::write_coordinates(int joint, const double* y, double* out) {
  const int n = joint_coordinate_count(joint);
  double value[kMaxJointCoordinates], rate[kMaxJointCoordinates];
  joint_coordinates(joint, y, value, rate);
  for (int c = 0; c < n; ++c) {
    out[2 * c] = value[c];
    out[2 * c + 1] = rate[c];
  }
  int k = 2 * n;
  for (int d : drivers_of_joint_[joint]) out[k++] = driving_effort(d, y);
  return k;
}

double MultibodyProblem::driving_effort(int driver, const double* y) {
  if (y != evaluated_y_) evaluate(0.0, y, 2);
  const ConstraintBlock& blk = blocks_[block_of_driver_[driver]];
  if (blk.lambda_group < 0) return 0.0;
  BlockSides sides;
  for (int x = 0; x < 2; ++x) {
    sides.body[x] = blk.body_of_side[x];
    sides.state[x] = sides.body[x] == kGround ? nullptr : &work_[sides.body[x]].st;
  }
  evaluate_rows(drivers_[driver].rows, drivers_[driver].row_count(), sides, driver_scratch_);
  return multibody::driving_effort(drivers_[driver], driver_scratch_, y[groups_[blk.lambda_group].offset]);
}

bool MultibodyProblem::has_work() const {
  if (!drivers_.empty()) return true;
  for (const auto& f : forces_)
    if (!f->conservative() && f->has_power()) return true;
  return false;
}

double MultibodyProblem::work_rate(double t, const double* y, bool just_evaluated) {
  if (!just_evaluated || !placement_evaluated_ || t != evaluated_t_) evaluate(t, y, 2);
  double power = 0.0;
  for (const auto& f : forces_)
    if (!f->conservative() && f->has_power()) power += f->power(force_bodies_);
  const double* keep = evaluated_y_;
  evaluated_y_ = y;
  power += driver_power(y);
  evaluated_y_ = keep;
  return power;
}

double MultibodyProblem::driver_power(const double* y) {
  double power = 0.0;
  for (int d = 0; d < static_cast<int>(drivers_.size()); ++d) {
    const DriverSpec& ds = spec_.drivers[d];
    double value[kMaxJointCoordinates], rate[kMaxJointCoordinates];
    joint_coordinates(ds.joint, y, value, rate);
    power += driving_effort(d, y) * rate[ds.coordinate];
  }
  return power;
}

}  // namespace rigidae::multibody
