// UrdfModel + initial joint state -> MultibodySpec (rigidae/io/urdf.hpp).
//
// The rules (docs/scene_format.md, "URDF"):
//   - the links and joints form one tree: every link is the child of at most
//     one joint, exactly one link (the root) of none, every link reachable;
//   - the ground: a root link named `world` IS the ground, and the joints out
//     of it say how the rest hangs (fixed: welded to the ground; floating:
//     free; revolute, continuous, prismatic: a joint to the ground). Without a
//     `world` link the root link is fixed to the ground (UrdfOptions::base =
//     Fixed, the default: an arm bolted down) or free (Floating). Links welded
//     to the ground are part of it: their mass is irrelevant and dropped;
//   - links joined by fixed joints form one rigid body, named after its top
//     link (nearest the root), whose frame axes are that link's and whose
//     origin is the combined centre of mass (combine_mass_parts); a floating
//     joint leaves its child free (no joint at all in rigidae);
//   - a body without mass that moves on a joint cannot be simulated (its
//     acceleration is undetermined): refused, unless nothing with mass hangs
//     from it, in which case it and its joint are dropped with a warning (a
//     tool frame on a joint carries no load); a body whose merged inertia is
//     singular (a point mass, a thin rod) is refused;
//   - revolute and continuous joints become revolute joints whose angle is
//     URDF's joint position (zero at the URDF's zero pose: the normals are
//     one vector fixed in the joint frame, carried by both links), prismatic
//     ones prismatic joints whose points coincide at position 0; <limit> is
//     kept as data (JointSpec::limits), not enforced; <dynamics damping> of a
//     revolute joint is its torsional damping.
//
// Forward kinematics of the initial state, link by link from the root, with
// joint frame J = parent frame * origin, u = R_J axis (space):
//   revolute:  R_C = R_J Rot(axis, q),  p_C = p_J,          w_C = w_P + u q',
//   prismatic: R_C = R_J,               p_C = p_J + u q,    w_C = w_P,
//   fixed, floating: R_C = R_J,         p_C = p_J,          w_C = w_P,
//   v_C = v_P + w_P x (p_C - p_P) (+ u q' for prismatic), v = a frame origin's velocity.
#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "rigidae/core/error.hpp"
#include "rigidae/core/text.hpp"
#include "rigidae/io/urdf.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::io {

MassPart combine_mass_parts(const std::vector<MassPart>& parts) {
  MassPart out;
  for (const MassPart& p : parts) {
    out.mass += p.mass;
    out.com += p.mass * p.com;
  }
  if (!(out.mass > 0.0)) return MassPart{};
  out.com /= out.mass;
  for (const MassPart& p : parts) {
    const Vec3 d = p.com - out.com;
    out.inertia += p.inertia + p.mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
  }
  out.inertia = 0.5 * (out.inertia + out.inertia.transpose());
  return out;
}

namespace {

constexpr std::string_view kWorld = "world";
constexpr std::size_t kMaxUrdfNameBytes = 64;
// A merged inertia whose smallest principal moment is below this fraction of
// its largest is taken as singular (a point mass or a thin rod).
constexpr double kSingularInertia = 1e-10;

struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 p = Vec3::Zero();
  Vec3 w = Vec3::Zero();  // angular velocity, space
  Vec3 v = Vec3::Zero();  // velocity of the frame origin, space
};

// A rigid group of links (a body, or the ground: group 0 when there is one).
struct Group {
  int top = -1;                          // link index
  std::vector<int> links;                // members, top first
  MassPart mass;                         // in the top link's frame
  bool ground = false;
  int body = -1;                         // index in MultibodySpec::bodies
};

// rigidae's part names become column names and folder names: letters, digits,
// '_' and '-', not starting with '-', at most 64 bytes, not "ground".
std::string part_name(const std::string& urdf_name) {
  std::string s;
  for (char c : urdf_name)
    s += ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-') ? c
                                                                                                             : '_';
  if (s.empty() || s.front() == '-') s = "_" + s;
  if (s.size() > kMaxUrdfNameBytes) s.resize(kMaxUrdfNameBytes);
  std::string low = s;
  for (char& c : low) c = text::lower(c);
  if (low == "ground") s += "_link";
  return s;
}

Vec3 default_normal(const Vec3& axis) {
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(axis[i]) < std::abs(axis[k])) k = i;
  const Vec3 e = Vec3::Unit(k);
  return (e - e.dot(axis) * axis).normalized();
}

class TreeBuilder {
 public:
  TreeBuilder(const UrdfModel& m, const UrdfOptions& o) : m_(m), o_(o) {}

  MultibodySpec build() {
    index();
    find_root();
    group_links();
    initial_poses();
    return spec();
  }

 private:
  const UrdfModel& m_;
  const UrdfOptions& o_;
  std::map<std::string, int, std::less<>> link_index_, joint_index_;
  std::vector<int> parent_joint_;           // per link: the joint it is the child of, or -1
  std::vector<std::vector<int>> children_;  // per link: joints out of it, in file order
  int root_ = -1;
  bool world_ = false;    // the root is `world`
  std::vector<int> order_;  // links from the root, parents before children
  std::vector<Group> groups_;
  std::vector<int> group_of_;  // per link
  std::vector<Pose> pose_;     // per link, initial
  std::vector<bool> dropped_;  // per group

  [[noreturn]] void fail(int line, const std::string& what) const {
    throw InputError(fmt::format("{}:{}: error: {}", m_.source, std::max(line, 1), what));
  }
  void warn(int line, const std::string& what) const {
    std::fprintf(stderr, "%s\n", fmt::format("{}:{}: warning: {}", m_.source, std::max(line, 1), what).c_str());
  }
  std::string link_label(int l) const { return fmt::format("<link name=\"{}\">", text::printable(m_.links[l].name)); }
  std::string joint_label(int j) const {
    return fmt::format("<joint name=\"{}\">", text::printable(m_.joints[j].name));
  }

  int link_named(const std::string& name, int joint, std::string_view role) const {
    const auto it = link_index_.find(name);
    if (it != link_index_.end()) return it->second;
    std::vector<std::string_view> names;
    for (const UrdfLink& l : m_.links) names.push_back(l.name);
    std::string msg = fmt::format("{}: <{} link=\"{}\"> names no link of this robot", joint_label(joint), role,
                                  text::printable(name));
    if (auto best = text::closest(name, names)) msg += fmt::format("; did you mean \"{}\"?", *best);
    fail(m_.joints[joint].line, msg);
  }

  void index() {
    for (std::size_t i = 0; i < m_.links.size(); ++i) link_index_[m_.links[i].name] = static_cast<int>(i);
    for (std::size_t i = 0; i < m_.joints.size(); ++i) joint_index_[m_.joints[i].name] = static_cast<int>(i);
    parent_joint_.assign(m_.links.size(), -1);
    children_.assign(m_.links.size(), {});
    for (int j = 0; j < static_cast<int>(m_.joints.size()); ++j) {
      const UrdfJoint& J = m_.joints[j];
      const int p = link_named(J.parent, j, "parent"), c = link_named(J.child, j, "child");
      if (parent_joint_[c] >= 0)
        fail(J.line, fmt::format("{}: link \"{}\" is already the child of {} (line {}); a URDF is a tree, each link "
                                 "the child of one joint (closed loops cannot be written in URDF: use a TOML scene)",
                                 joint_label(j), text::printable(J.child), joint_label(parent_joint_[c]),
                                 m_.joints[parent_joint_[c]].line));
      parent_joint_[c] = j;
      children_[p].push_back(j);
    }
  }

  void find_root() {
    std::vector<int> roots;
    for (int l = 0; l < static_cast<int>(m_.links.size()); ++l)
      if (parent_joint_[l] < 0) roots.push_back(l);
    if (roots.empty())
      fail(m_.links.front().line, "every link is the child of a joint, so the joints form a loop and there is no root "
                                  "link; a URDF is a tree with one root link");
    if (roots.size() > 1) {
      std::string list;
      for (std::size_t k = 0; k < roots.size() && k < 8; ++k)
        list += fmt::format("{}\"{}\" (line {})", k ? ", " : "", text::printable(m_.links[roots[k]].name),
                            m_.links[roots[k]].line);
      fail(m_.links[roots[1]].line,
           fmt::format("{} links are the child of no joint: {}{}; a URDF is one tree with one root link (join the "
                       "others to it, or to a `world` link)",
                       roots.size(), list, roots.size() > 8 ? ", ..." : ""));
    }
    root_ = roots.front();
    world_ = m_.links[root_].name == kWorld;
    if (world_ && o_.base)
      throw InputError(fmt::format("{}: error: 'base' is set, but {} has a `world` link: the joints out of `world` "
                                   "decide how the robot is held (fixed, floating, or a moving joint); remove "
                                   "'base'",
                                   o_.base_where.empty() ? m_.source : o_.base_where, m_.source));
    // Every link reachable from the root (a loop elsewhere would not be).
    std::vector<int> stack{root_};
    while (!stack.empty()) {
      const int l = stack.back();
      stack.pop_back();
      order_.push_back(l);
      for (auto it = children_[l].rbegin(); it != children_[l].rend(); ++it)
        stack.push_back(link_index_.at(m_.joints[*it].child));
    }
    if (order_.size() != m_.links.size()) {
      std::vector<bool> seen(m_.links.size());
      for (int l : order_) seen[l] = true;
      const int l = static_cast<int>(std::find(seen.begin(), seen.end(), false) - seen.begin());
      fail(m_.links[l].line, fmt::format("{} cannot be reached from the root link \"{}\": its joints form a loop; a "
                                         "URDF is a tree",
                                         link_label(l), text::printable(m_.links[root_].name)));
    }
  }

  // The frame of link `l` in its group's top link frame.
  UrdfFrame in_top(int l) const {
    UrdfFrame f;
    while (l != groups_[group_of_[l]].top) {
      const UrdfJoint& J = m_.joints[parent_joint_[l]];
      f = UrdfFrame{J.origin.R * f.R, J.origin.R * f.t + J.origin.t};
      l = link_index_.at(J.parent);
    }
    return f;
  }

  void group_links() {
    group_of_.assign(m_.links.size(), -1);
    const bool root_is_ground = world_ || o_.base.value_or(UrdfBase::Fixed) == UrdfBase::Fixed;
    for (int l : order_) {
      const int j = parent_joint_[l];
      if (j >= 0 && m_.joints[j].type == UrdfJointType::Fixed) {
        group_of_[l] = group_of_[link_index_.at(m_.joints[j].parent)];
      } else {
        group_of_[l] = static_cast<int>(groups_.size());
        Group g;
        g.top = l;
        g.ground = j < 0 && root_is_ground;
        groups_.push_back(g);
      }
      groups_[group_of_[l]].links.push_back(l);
    }
    dropped_.assign(groups_.size(), false);
    // Masses, leaves first: a massless group with massive groups below is
    // refused, one with nothing massive below is dropped.
    std::vector<bool> massive_below(groups_.size(), false);
    for (auto it = order_.rbegin(); it != order_.rend(); ++it) {
      const int l = *it;
      Group& g = groups_[group_of_[l]];
      if (g.top != l) continue;
      std::vector<MassPart> parts;
      for (int k : g.links) {
        const auto& in = m_.links[k].inertial;
        if (!in) continue;
        const UrdfFrame f = in_top(k);
        const Mat3 R = f.R * in->origin.R;
        parts.push_back({in->mass, f.R * in->origin.t + f.t, R * in->inertia * R.transpose()});
      }
      g.mass = combine_mass_parts(parts);
      const int gi = group_of_[l];
      if (g.ground) continue;
      const bool has_mass = g.mass.mass > 0.0;
      if (!has_mass) {
        if (!massive_below[gi]) {
          dropped_[gi] = true;
          continue;
        }
        const int j = parent_joint_[l];
        fail(m_.links[l].line,
             fmt::format("{} has no mass (no <inertial>, or mass 0{}) but moves on {} while links with mass hang "
                         "from it: its motion would be undetermined; give it an <inertial> (a small mass and "
                         "inertia will do), or join it to its parent by a fixed joint",
                         link_label(l), g.links.size() > 1 ? ", nor the links fixed to it" : "",
                         j >= 0 ? joint_label(j) : std::string("its floating base")));
      }
      const Eigen::SelfAdjointEigenSolver<Mat3> eig(g.mass.inertia);
      const Vec3 J = eig.eigenvalues();
      if (!(J[0] > kSingularInertia * J[2])) {
        std::string members;
        for (std::size_t k = 0; k < g.links.size(); ++k)
          members += fmt::format("{}\"{}\"", k ? ", " : "", text::printable(m_.links[g.links[k]].name));
        fail(m_.links[l].line,
             fmt::format("the rigid body of link{} {} has a singular inertia (principal moments {:.3g}, {:.3g}, "
                         "{:.3g} kg m^2 about its centre of mass): a point mass or a thin rod cannot turn in 3D; "
                         "give its <inertia> non-zero moments about every axis",
                         g.links.size() > 1 ? "s" : "", members, J[0], J[1], J[2]));
      }
      // Propagate to the parent group.
      const int j = parent_joint_[l];
      if (j >= 0) massive_below[group_of_[link_index_.at(m_.joints[j].parent)]] = true;
    }
    // A dropped group drops everything below it (all massless, by the above).
    for (int l : order_) {
      const int j = parent_joint_[l];
      if (j >= 0 && dropped_[group_of_[link_index_.at(m_.joints[j].parent)]]) dropped_[group_of_[l]] = true;
    }
    for (int l : order_)
      if (groups_[group_of_[l]].top == l && dropped_[group_of_[l]] && parent_joint_[l] >= 0 &&
          !dropped_[group_of_[link_index_.at(m_.joints[parent_joint_[l]].parent)]])
        warn(m_.links[l].line, fmt::format("{} and what hangs from it have no mass: dropped with {} (they carry no "
                                           "load and do not change the motion)",
                                           link_label(l), joint_label(parent_joint_[l])));
  }

  double state_of(const std::vector<UrdfJointState>& values, int j) const {
    for (const UrdfJointState& s : values)
      if (s.joint == m_.joints[j].name) return s.value;
    return 0.0;
  }

  void check_state(const std::vector<UrdfJointState>& values, std::string_view what) const {
    std::vector<std::string_view> movable;
    for (const UrdfJoint& J : m_.joints)
      if (J.type != UrdfJointType::Fixed && J.type != UrdfJointType::Floating) movable.push_back(J.name);
    for (const UrdfJointState& s : values) {
      const std::string at = s.where.empty() ? m_.source : s.where;
      const auto it = joint_index_.find(s.joint);
      if (it == joint_index_.end()) {
        std::string msg = fmt::format("{}: error: {} names joint \"{}\", which is not in {}", at, what,
                                      text::printable(s.joint), m_.source);
        if (auto best = text::closest(s.joint, movable)) msg += fmt::format("; did you mean \"{}\"?", *best);
        throw InputError(msg + fmt::format(" (movable joints: {})", text::quoted_list(movable)));
      }
      const UrdfJoint& J = m_.joints[it->second];
      if (J.type == UrdfJointType::Fixed || J.type == UrdfJointType::Floating)
        throw InputError(fmt::format("{}: error: {} gives a value to the {} joint \"{}\" ({}:{}), which has no "
                                     "position or rate of its own (movable joints: {})",
                                     at, what, J.type == UrdfJointType::Fixed ? "fixed" : "floating",
                                     text::printable(s.joint), m_.source, J.line, text::quoted_list(movable)));
    }
  }

  void initial_poses() {
    check_state(o_.positions, "[urdf] positions");
    check_state(o_.velocities, "[urdf] velocities");
    pose_.assign(m_.links.size(), Pose{});
    for (int l : order_) {
      const int j = parent_joint_[l];
      if (j < 0) continue;  // the root: the space frame (ground, or a free base starting there at rest)
      const UrdfJoint& J = m_.joints[j];
      const Pose& P = pose_[link_index_.at(J.parent)];
      Pose& C = pose_[l];
      const Mat3 RJ = P.R * J.origin.R;
      const Vec3 pJ = P.p + P.R * J.origin.t;
      const Vec3 u = RJ * J.axis;
      const double q = state_of(o_.positions, j), qd = state_of(o_.velocities, j);
      C.R = RJ;
      C.p = pJ;
      C.w = P.w;
      switch (J.type) {
        case UrdfJointType::Revolute:
        case UrdfJointType::Continuous:
          C.R = RJ * so3::axis_angle_to_matrix(J.axis, q);
          C.w = P.w + u * qd;
          break;
        case UrdfJointType::Prismatic:
          C.p = pJ + u * q;
          break;
        default:
          break;
      }
      C.v = P.v + P.w.cross(C.p - P.p);
      if (J.type == UrdfJointType::Prismatic) C.v += u * qd;
      if (J.limits && J.limits->lower && J.limits->upper && (q < *J.limits->lower || q > *J.limits->upper))
        warn(J.line, fmt::format("{} starts at {:g}, outside its limits [{:g}, {:g}] (limits are kept as data, not "
                                 "enforced)",
                                 joint_label(j), q, *J.limits->lower, *J.limits->upper));
    }
  }

  MultibodySpec spec() {
    MultibodySpec s;
    std::set<std::string> names;
    const auto claim = [&](std::string name, const std::string& urdf_name, int line, std::string_view kind) {
      if (name != urdf_name)
        warn(line, fmt::format("{} name \"{}\" becomes \"{}\" in rigidae (names are column and folder names: "
                               "letters, digits, '_' and '-')",
                               kind, text::printable(urdf_name), name));
      if (!names.insert(name).second) {
        const std::string renamed = name + "_" + std::string(kind);
        if (!names.insert(renamed).second)
          fail(line, fmt::format("{} name \"{}\" clashes with another part's name in rigidae; rename one",
                                 kind, text::printable(urdf_name)));
        return renamed;
      }
      return name;
    };
    int dof = 0;
    for (int l : order_) {
      Group& g = groups_[group_of_[l]];
      if (g.top != l || g.ground || dropped_[group_of_[l]]) continue;
      const Pose& P = pose_[l];
      BodySpec b;
      b.name = claim(part_name(m_.links[l].name), m_.links[l].name, m_.links[l].line, "link");
      b.mass = g.mass.mass;
      b.inertia_com = g.mass.inertia;
      const Vec3 c_W = P.R * g.mass.com;
      b.x0_W = P.p + c_W;
      b.R0_WB = P.R;
      b.v0_W = P.v + P.w.cross(c_W);
      b.omega0_B = P.R.transpose() * P.w;
      b.where = {m_.source, m_.links[l].line, 0};
      g.body = static_cast<int>(s.bodies.size());
      s.bodies.push_back(b);
      const int j = parent_joint_[l];
      if (j < 0 || m_.joints[j].type == UrdfJointType::Floating) dof += 6;
    }
    for (int l : order_) {
      const int j = parent_joint_[l];
      if (j < 0 || dropped_[group_of_[l]]) continue;
      const UrdfJoint& J = m_.joints[j];
      if (J.type == UrdfJointType::Fixed || J.type == UrdfJointType::Floating) continue;
      const int pl = link_index_.at(J.parent);
      const Group& ga = groups_[group_of_[pl]];
      const Group& gb = groups_[group_of_[l]];
      JointSpec js;
      js.name = claim(part_name(J.name), J.name, J.line, "joint");
      js.type = &joint_type(J.type == UrdfJointType::Prismatic ? "prismatic" : "revolute");
      // The joint frame in body a's frame (its top link's axes, from its
      // centre of mass), or in space for the ground.
      UrdfFrame f = in_top(pl);
      Mat3 R_AJ = f.R * J.origin.R;
      Vec3 o_A = f.R * J.origin.t + f.t;
      if (ga.ground) {
        const Pose& top = pose_[ga.top];  // the space frame
        R_AJ = top.R * R_AJ;
        o_A = top.p + top.R * o_A;
      } else {
        o_A -= ga.mass.com;
      }
      const Vec3 n = default_normal(J.axis);
      js.body_a = ga.ground ? kGround : ga.body;
      js.body_b = gb.body;
      js.point_a = o_A;
      js.axis_a = R_AJ * J.axis;
      js.normal_a = R_AJ * n;
      // The child link is body b's top: its frame is the joint frame at
      // position 0, so axis and normal have the joint frame's components.
      js.point_b = -gb.mass.com;
      js.axis_b = J.axis;
      js.normal_b = n;
      js.torsion_damping = J.damping;
      js.limits = J.limits;
      js.where = {m_.source, J.line, 0};
      s.joints.push_back(js);
      ++dof;
    }
    if (s.bodies.empty())
      fail(m_.links[root_].line, fmt::format("nothing moves: every link is welded to the ground or massless (root "
                                             "link \"{}\"{}); give the robot moving joints and links with "
                                             "<inertial>, or set base = \"floating\"",
                                             text::printable(m_.links[root_].name),
                                             world_ ? "" : ", fixed to the ground as no `world` link says otherwise"));
    s.expected_dof = dof;
    s.expected_dof_where = {m_.source, 1, 0};
    return s;
  }
};

}  // namespace

MultibodySpec urdf_to_multibody(const UrdfModel& model, const UrdfOptions& options) {
  return TreeBuilder(model, options).build();
}

}  // namespace rigidae::io
