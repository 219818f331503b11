// A scene as an MJCF model (rigidae/io/mjcf_export.hpp): the system it runs
// as (as_system), so a one-body scene is its one body held at a pivot.
//
// MJCF bodies nest: each body is placed in its parent's frame and carries the
// joints that move it relative to that parent, so the joints must form a tree.
// The tree is found from the ground: bodies reached through joints, in scene
// order, hang from the body they were reached from; a joint between two
// bodies already reached closes a loop and is refused (MJCF would need an
// equality constraint and a different choice of tree). Bodies not connected
// to the ground hang from a free joint (<freejoint>) at the top level. A body
// held at a pivot (BodySpec::pivot_W: a one-body scene's top at its fixed
// point, a free body at its centre of mass, or a schema-2 body with `pivot`)
// hangs from the ground by a ball joint NAME_pivot at the pivot, reached
// before the ground's joints (a joint that then reaches it again closes a
// loop).
//
// Frames: an MJCF body's frame is the rigidae body's frame (origin at the
// centre of mass, the scene's body axes); <inertial pos="0 0 0" quat
// diaginertia> is BodySpec::inertia_com in its principal axes (quat turns
// the body axes onto them). A body's pos/quat in its
// parent's frame is their relative pose at the model's reference
// configuration (qpos = 0):
//   revolute, prismatic, cylindrical: the joint points coincide and the
//     frames F = [n, z x n, z] of both sides agree: R_pc = F_p F_c^T,
//     t_pc = point_p - R_pc point_c; so qpos is rigidae's joint angle
//     (atan2 of the normals, multibody/torsion.cpp) and slide (p_b - p_a) . z_a;
//   spherical, universal, fixed (no coordinate of their own): the initial
//     relative pose, where qpos = 0 (ball: the identity quaternion).
// Joint axes in the child frame: the child side's axis, negated when the
// child is the joint's first body (a), so that qpos keeps rigidae's sign
// (b relative to a). A universal joint is two hinges in one body: first about
// the parent's pin (a body-fixed axis of the parent), then the child's own.
//
// The initial state is the keyframe "initial" (mj_resetDataKeyframe(m, d, 0)):
//   hinge qpos = the angle, qvel = (w_b - w_a) . z_a;
//   slide qpos = (p_b - p_a) . z_a, qvel = (v(p_b) - v(p_a)) . z_a;
//   ball  qpos = (1 0 0 0), qvel = R_c^T (w_c - w_p) (child axes); a pivot's
//         ball: qvel = omega0_B;
//   free  qpos = (x, quat), qvel = (v world, w body axes);
//   universal: the two rates that make (w_c - w_p), least squares.
//
// Written: gravity, timestep, integrator, contacts off (<flag contact
// ="disable">; the geoms are drawings only: contype = conaffinity = 0, no
// mass), torsional springs and dampers (stiffness, springref, damping),
// limits as range with limited="false" (data, not enforced, as in rigidae).
// Refused: closed loops, particles, springs and loads (MJCF has no
// constant body load, and a two-point spring is a tendon this writer does not
// write), drivers and motors (time functions: MuJoCo's actuators and their
// controls live at run time).
#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "rigidae/core/error.hpp"
#include "rigidae/io/mjcf_export.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::io {
namespace {

std::string num(double x) {
  if (x == 0.0) return "0";
  return fmt::format("{:.17g}", x);
}
std::string vec(const Vec3& v) { return fmt::format("{} {} {}", num(v[0]), num(v[1]), num(v[2])); }
std::string quat(const Mat3& R) {
  const Vec4 q = so3::matrix_to_quaternion(R);
  return fmt::format("{} {} {} {}", num(q[0]), num(q[1]), num(q[2]), num(q[3]));
}

Mat3 frame(const Vec3& z, const Vec3& n) {
  Mat3 F;
  F.col(0) = n;
  F.col(1) = z.cross(n);
  F.col(2) = z;
  return F;
}

struct Edge {
  int joint = -1;     // index into joints, -1 for a top-level body (free, or on its pivot)
  int parent = -1;    // body index, or kGround
  bool child_is_b = true;
  bool pivot = false;  // a top-level body held at its pivot by a ball joint
};

class Writer {
 public:
  Writer(const Scene& s, const MjcfOptions& o, std::string main_name)
      : s_(s), mb_(*s.multibody), o_(o), main_(std::move(main_name)) {}

  std::vector<std::pair<std::string, std::string>> write() {
    refuse_what_mjcf_lacks();
    build_tree();
    std::string xml = fmt::format(
        "<!-- {}: written by rigidae {} from {} (`rigidae export --mjcf`).\n"
        "     Body frames: origin at the centre of mass, the scene's body axes. Joint\n"
        "     positions at qpos = 0 are rigidae's zeros; the initial state is keyframe 0.\n"
        "     Limits are data (limited=\"false\"): rigidae does not enforce them either. -->\n"
        "<mujoco model=\"{}\">\n"
        "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
        "  <option timestep=\"{}\" integrator=\"{}\" gravity=\"{}\">\n"
        "    <flag contact=\"disable\"/>\n"
        "  </option>\n"
        "  <worldbody>\n",
        main_, RIGIDAE_VERSION, comment_safe(s_.source.empty() ? s_.name : s_.source), s_.name, num(o_.timestep),
        o_.integrator, vec(mb_.gravity_W));
    for (int b : children_[kGroundNode]) emit(b, 4, 0, xml);
    xml += "  </worldbody>\n";
    xml += keyframe();
    xml += "</mujoco>\n";
    std::vector<std::pair<std::string, std::string>> files{{main_, xml}};
    for (auto& p : parts_) files.push_back(std::move(p));
    return files;
  }

 private:
  static constexpr int kGroundNode = 0;  // node = body + 1
  const Scene& s_;
  const MultibodySpec& mb_;
  const MjcfOptions& o_;
  std::string main_;
  std::vector<Edge> edge_;                  // per body
  std::vector<std::vector<int>> children_;  // per node: bodies
  std::vector<double> qpos_, qvel_;
  std::vector<std::pair<std::string, std::string>> parts_;

  static std::string comment_safe(std::string t) {
    for (std::size_t k; (k = t.find("--")) != std::string::npos;) t.replace(k, 2, "- -");
    return t;
  }

  [[noreturn]] void refuse(const SourcePosition& at, const std::string& what) const {
    throw InputError(fmt::format("{}:{}:{}: error: {}", at.file.empty() ? s_.source : at.file, std::max(at.line, 1),
                                 std::max(at.column, 1), what));
  }

  void refuse_what_mjcf_lacks() const {
    if (!mb_.springs.empty())
      refuse(mb_.springs.front().where,
             fmt::format("spring \"{}\": MJCF export writes bodies and joints, not two-point springs (a spatial "
                         "tendon); export a scene without [[springs]]",
                         mb_.springs.front().name));
    for (const BodySpec& b : mb_.bodies)
      if (b.particle)
        refuse(b.where, fmt::format("body \"{}\" is a particle (kind = \"particle\"): MJCF has no point mass without "
                                    "inertia (a MuJoCo body needs positive principal moments); give it a small inertia "
                                    "as a rigid body to export the scene",
                                    b.name));
    if (!mb_.loads.empty())
      refuse(mb_.loads.front().where, "[[loads]]: MJCF has no constant body load (MuJoCo applies such forces at run "
                                      "time through xfrc_applied); export a scene without [[loads]]");
    // Prescribed motion and motors act through time functions that MJCF
    // cannot state in the model (MuJoCo drives joints through actuators and
    // controls set at run time): dropping them would export another motion.
    if (!mb_.drivers.empty()) {
      const DriverSpec& d = mb_.drivers.front();
      refuse(d.where, fmt::format("[[drivers]] on joint \"{}\": MJCF states no prescribed joint motion f(t) (MuJoCo "
                                  "drives a joint through an actuator and its control at run time); export the scene "
                                  "without [[drivers]]",
                                  mb_.joints[static_cast<std::size_t>(d.joint)].name));
    }
    for (const JointSpec& J : mb_.joints)
      if (J.motor_torque != 0.0 || J.motor_force != 0.0)
        refuse(J.where, fmt::format("joint \"{}\" has a motor ({}): MJCF states no joint load as a function of time "
                                    "(MuJoCo applies it through an actuator's control at run time); export the scene "
                                    "without the motor",
                                    J.name, J.motor_torque != 0.0 ? "motor_torque" : "motor_force"));
  }

  std::string body_label(int b) const { return b == kGround ? std::string("the ground") : "\"" + mb_.bodies[b].name + "\""; }

  void build_tree() {
    const int nb = static_cast<int>(mb_.bodies.size());
    edge_.assign(nb, Edge{});
    children_.assign(nb + 1, {});
    std::vector<bool> reached(nb + 1, false);
    std::vector<int> via(nb + 1, -1);  // the joint a node was reached through
    std::vector<bool> used(mb_.joints.size(), false);
    const auto grow = [&](std::vector<int> queue) {
      for (int node : queue) reached[node] = true;
      for (std::size_t qi = 0; qi < queue.size(); ++qi) {
        const int node = queue[qi];
        const int body = node - 1;
        for (int j = 0; j < static_cast<int>(mb_.joints.size()); ++j) {
          const JointSpec& J = mb_.joints[j];
          if (used[j] || (J.body_a != body && J.body_b != body)) continue;
          const int other = J.body_a == body ? J.body_b : J.body_a;
          used[j] = true;
          if (reached[other + 1])
            refuse(J.where,
                   fmt::format("joint \"{}\" closes a loop: {} and {} are already joined through other joints (or a "
                               "pivot). MJCF "
                               "bodies nest as a tree, so a closed loop needs an equality constraint, which this "
                               "export does not write; export a tree-structured mechanism (cut the loop at one "
                               "joint to see the rest)",
                               J.name, body_label(body), body_label(other)));
          reached[other + 1] = true;
          edge_[other] = Edge{j, body, J.body_b == other};
          children_[node].push_back(other);
          queue.push_back(other + 1);
        }
      }
    };
    // The ground, then the bodies on their pivots (hanging from it), then
    // what the joints reach from these.
    std::vector<int> from_ground{kGroundNode};
    for (int b = 0; b < nb; ++b)
      if (mb_.bodies[b].pivot_W) {
        edge_[b] = Edge{-1, kGround, true, true};
        children_[kGroundNode].push_back(b);
        from_ground.push_back(b + 1);
      }
    grow(from_ground);
    for (int b = 0; b < nb; ++b)
      if (!reached[b + 1]) {
        edge_[b] = Edge{-1, kGround, true};
        children_[kGroundNode].push_back(b);
        grow({b + 1});
      }
  }

  // Initial pose of a body (the ground: the space frame).
  Mat3 R0(int b) const { return b == kGround ? Mat3::Identity() : mb_.bodies[b].R0_WB; }
  Vec3 x0(int b) const { return b == kGround ? Vec3::Zero() : mb_.bodies[b].x0_W; }
  Vec3 w0(int b) const { return b == kGround ? Vec3::Zero() : Vec3(R0(b) * mb_.bodies[b].omega0_B); }
  Vec3 v0_at(int b, const Vec3& p_W) const {
    return b == kGround ? Vec3::Zero() : Vec3(mb_.bodies[b].v0_W + w0(b).cross(p_W - x0(b)));
  }

  void emit(int b, int indent, int depth_in_file, std::string& xml) {
    const BodySpec& B = mb_.bodies[b];
    const Edge& e = edge_[b];
    const std::string pad(static_cast<std::size_t>(indent), ' ');
    Mat3 R_pc;
    Vec3 t_pc;
    std::string joints;
    const int p = e.parent;
    if (e.pivot) {  // on its pivot, at the top level: a ball joint there
      R_pc = B.R0_WB;
      t_pc = B.x0_W;
      const Vec3 lever = B.com_from_pivot_B.value_or(Vec3(B.R0_WB.transpose() * (B.x0_W - *B.pivot_W)));
      joints = fmt::format("{}  <joint name=\"{}_pivot\" type=\"ball\" pos=\"{}\"/>\n", pad, B.name, vec(-lever));
      qpos_.insert(qpos_.end(), {1.0, 0.0, 0.0, 0.0});
      for (int k = 0; k < 3; ++k) qvel_.push_back(B.omega0_B[k]);
    } else if (e.joint < 0) {  // free, at the top level
      R_pc = B.R0_WB;
      t_pc = B.x0_W;
      joints = fmt::format("{}  <freejoint name=\"{}_free\"/>\n", pad, B.name);
      const Vec4 q = so3::matrix_to_quaternion(B.R0_WB);
      for (int k = 0; k < 3; ++k) qpos_.push_back(B.x0_W[k]);
      for (int k = 0; k < 4; ++k) qpos_.push_back(q[k]);
      for (int k = 0; k < 3; ++k) qvel_.push_back(B.v0_W[k]);
      for (int k = 0; k < 3; ++k) qvel_.push_back(B.omega0_B[k]);
    } else {
      const JointSpec& J = mb_.joints[e.joint];
      const double sign = e.child_is_b ? 1.0 : -1.0;
      const Vec3 point_c = e.child_is_b ? J.point_b : J.point_a, point_p = e.child_is_b ? J.point_a : J.point_b;
      const Vec3 axis_c = e.child_is_b ? J.axis_b : J.axis_a, axis_p = e.child_is_b ? J.axis_a : J.axis_b;
      const Vec3 normal_c = e.child_is_b ? J.normal_b : J.normal_a, normal_p = e.child_is_b ? J.normal_a : J.normal_b;
      // Space quantities at the initial pose, on sides a and b.
      const Mat3 Ra = R0(J.body_a), Rb = R0(J.body_b);
      const Vec3 za = Ra * J.axis_a, na = Ra * J.normal_a, nb = Rb * J.normal_b;
      const Vec3 pa = Ra * J.point_a + x0(J.body_a), pb = Rb * J.point_b + x0(J.body_b);
      const Vec3 w_rel = w0(J.body_b) - w0(J.body_a);
      const std::string_view type = J.type->name;
      const bool has_coordinate = type == "revolute" || type == "prismatic" || type == "cylindrical";
      if (has_coordinate) {
        R_pc = frame(axis_p, normal_p) * frame(axis_c, normal_c).transpose();
        t_pc = point_p - R_pc * point_c;
      } else {
        R_pc = R0(p).transpose() * B.R0_WB;
        t_pc = R0(p).transpose() * (B.x0_W - x0(p));
      }
      const std::string axis = vec(sign * axis_c);
      const std::string where = vec(point_c);
      const double angle = std::atan2(za.cross(na).dot(nb), na.dot(nb));
      const double slide = (pb - pa).dot(za);
      std::string range;
      if (J.limits && J.limits->lower && J.limits->upper)
        range = fmt::format(" limited=\"false\" range=\"{} {}\"", num(*J.limits->lower), num(*J.limits->upper));
      const auto hinge = [&](const std::string& name, const std::string& ax, const std::string& extra) {
        joints += fmt::format("{}  <joint name=\"{}\" type=\"hinge\" pos=\"{}\" axis=\"{}\"{}/>\n", pad, name, where,
                              ax, extra);
      };
      const auto slider = [&](const std::string& name, const std::string& extra) {
        joints += fmt::format("{}  <joint name=\"{}\" type=\"slide\" pos=\"{}\" axis=\"{}\"{}/>\n", pad, name, where,
                              axis, extra);
      };
      // MJCF joints per registered type (model/joint_type.hpp); a type not
      // listed here is refused.
      if (type == "revolute") {
          std::string extra = range;
          if (J.torsion_stiffness != 0.0)
            extra += fmt::format(" stiffness=\"{}\" springref=\"{}\"", num(J.torsion_stiffness),
                                 num(J.torsion_rest_angle));
          if (J.torsion_damping != 0.0) extra += fmt::format(" damping=\"{}\"", num(J.torsion_damping));
          hinge(J.name, axis, extra);
          qpos_.push_back(angle);
          qvel_.push_back(w_rel.dot(za));
      } else if (type == "prismatic") {
          slider(J.name, range);
          qpos_.push_back(slide);
          qvel_.push_back((v0_at(J.body_b, pb) - v0_at(J.body_a, pa)).dot(za));
      } else if (type == "cylindrical") {
          slider(J.name + "_slide", range);
          hinge(J.name + "_hinge", axis, "");
          qpos_.push_back(slide);
          qvel_.push_back((v0_at(J.body_b, pb) - v0_at(J.body_a, pa)).dot(za));
          qpos_.push_back(angle);
          qvel_.push_back(w_rel.dot(za));
      } else if (type == "spherical") {
          joints += fmt::format("{}  <joint name=\"{}\" type=\"ball\" pos=\"{}\"/>\n", pad, J.name, where);
          const Vec3 w = B.R0_WB.transpose() * (w0(b) - w0(p));
          qpos_.insert(qpos_.end(), {1.0, 0.0, 0.0, 0.0});
          qvel_.insert(qvel_.end(), {w[0], w[1], w[2]});
      } else if (type == "universal") {
          // The parent's pin, in the child's axes at the initial pose, then the child's.
          const Vec3 pin_p_W = R0(p) * axis_p, pin_c_W = B.R0_WB * axis_c;
          hinge(J.name + "_1", vec(B.R0_WB.transpose() * pin_p_W), "");
          hinge(J.name + "_2", vec(axis_c), "");
          Eigen::Matrix<double, 3, 2> A;
          A << pin_p_W, pin_c_W;
          const Eigen::Vector2d rates = A.colPivHouseholderQr().solve(w0(b) - w0(p));
          qpos_.insert(qpos_.end(), {0.0, 0.0});
          qvel_.insert(qvel_.end(), {rates[0], rates[1]});
      } else if (type != "fixed") {  // fixed: no joint: MJCF welds a body without joints to its parent
        throw InputError(fmt::format("joint '{}': the MJCF export has no mapping for a {} joint", J.name, type));
      }
    }
    xml += fmt::format("{}<body name=\"{}\" pos=\"{}\" quat=\"{}\">\n", pad, B.name, vec(t_pc), quat(R_pc));
    xml += joints;
    // Principal moments and axes, diagonalised here (Eigen, to round-off):
    // MuJoCo 2.2's own diagonalisation of `fullinertia` (mju_eig3) stops at
    // an absolute tolerance, which on small inertias (1e-4 kg m^2) left
    // relative errors near 1e-9 -- enough to move the arm6 cross-check's
    // joint angles by 1e-4 rad after 1 s of its sensitive motion.
    const Mat3& I = B.inertia_com;
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(I);
    Mat3 V = eig.eigenvectors();
    if (V.determinant() < 0.0) V.col(2) = -V.col(2);
    xml += fmt::format("{}  <inertial pos=\"0 0 0\" quat=\"{}\" mass=\"{}\" diaginertia=\"{}\"/>\n", pad, quat(V),
                       num(B.mass), vec(eig.eigenvalues()));
    // A drawing: the sphere of the body's mean moment (I = 2/5 m r^2), no mass, no contact.
    const double r = std::sqrt(2.5 * I.trace() / 3.0 / B.mass);
    xml += fmt::format("{}  <geom type=\"sphere\" size=\"{}\" contype=\"0\" conaffinity=\"0\" mass=\"0\"/>\n", pad,
                       num(r));
    const std::vector<int>& kids = children_[b + 1];
    if (!kids.empty()) {
      if (depth_in_file + 1 >= o_.bodies_per_file) {
        // MuJoCo's XML reader stops at 100 nested elements: continue in a file of its own.
        const std::filesystem::path stem = std::filesystem::path(main_).stem();
        const std::string part = fmt::format("{}.part{}.xml", stem.string(), parts_.size() + 1);
        parts_.emplace_back(part, "");
        const std::size_t slot = parts_.size() - 1;
        xml += fmt::format("{}  <include file=\"{}\"/>\n", pad, part);
        std::string sub = "<mujoco>\n";
        for (int c : kids) emit(c, 0, 0, sub);
        sub += "</mujoco>\n";
        parts_[slot].second = std::move(sub);
      } else {
        for (int c : kids) emit(c, indent + 2, depth_in_file + 1, xml);
      }
    }
    xml += fmt::format("{}</body>\n", pad);
  }

  std::string keyframe() const {
    if (qpos_.empty()) return "";
    std::string q, v;
    for (double x : qpos_) q += (q.empty() ? "" : " ") + num(x);
    for (double x : qvel_) v += (v.empty() ? "" : " ") + num(x);
    return fmt::format("  <keyframe>\n    <key name=\"initial\" qpos=\"{}\" qvel=\"{}\"/>\n  </keyframe>\n", q, v);
  }
};

}  // namespace

std::vector<std::pair<std::string, std::string>> mjcf_files(const Scene& scene, const MjcfOptions& options,
                                                            const std::string& main_name) {
  if (options.bodies_per_file < 1) throw InputError("MJCF export: bodies_per_file must be at least 1");
  const Scene system = as_system(scene);
  return Writer(system, options, main_name).write();
}

}  // namespace rigidae::io
