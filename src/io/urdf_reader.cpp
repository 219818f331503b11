// URDF text -> UrdfModel (rigidae/io/urdf.hpp), read with tinyxml2.
//
// Why tinyxml2 and not Debian's urdfdom 3.0 (liburdfdom-dev): urdfdom reports
// errors through console_bridge with the line of ITS OWN source file ("at line
// 299 in ./urdf_parser/src/link.cpp"), never the URDF's, and returns only a
// null model; and it accepts what cannot be simulated (a negative mass, an
// inertia that is not positive semi-definite, an all-zero <axis>), which would
// all need checking again here without a position to report. Reading the few
// elements that carry dynamics directly gives every message its line.
//
// Read: <robot name>, <link name> with <inertial> (<origin xyz rpy>, <mass
// value>, <inertia ixx ixy ixz iyy iyz izz>), <joint name type> with
// <parent link>, <child link>, <origin>, <axis xyz>, <limit lower upper effort
// velocity>, <dynamics damping friction>. Ignored: <visual>, <collision>,
// <material>, <transmission>, <gazebo> and other extensions (they do not
// change the motion); <calibration> and <safety_controller> (no effect
// without a controller). Refused with the reason: planar joints, <mimic>,
// friction, damping on prismatic joints (rigidae has no such forces).
//
// Angles: rpy is roll about x, then pitch about y, then yaw about z, all
// about the parent's fixed axes: R = Rz(yaw) Ry(pitch) Rx(roll).
#include <fmt/format.h>
#include <tinyxml2.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "rigidae/core/error.hpp"
#include "rigidae/core/text.hpp"
#include "rigidae/io/urdf.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::io {
namespace {

using tinyxml2::XMLElement;

constexpr double kMaxLength = 1e6;   // m: origins (wrong units beyond)
constexpr double kMaxUrdfMass = 1e9;     // kg
constexpr double kMaxInertia = 1e12; // kg m^2
// Relative slack in the triangle inequality and positive semi-definiteness
// of an inertia (written values are rounded to a few digits).
constexpr double kInertiaSlack = 1e-9;

constexpr std::array<std::string_view, 6> kJointTypes{"revolute", "continuous", "prismatic",
                                                      "fixed",    "floating",   "planar"};

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const XMLElement* e, const std::string& what) const {
    throw InputError(fmt::format("{}:{}: error: {}: {}", file_, e ? e->GetLineNum() : 1, label(e), what));
  }
  void warn(const XMLElement* e, const std::string& what) const {
    std::fprintf(stderr, "%s\n", fmt::format("{}:{}: warning: {}: {}", file_, e->GetLineNum(), label(e), what).c_str());
  }

  // <joint name="elbow">, or <mass> inside <link name="arm">.
  static std::string label(const XMLElement* e) {
    if (!e) return "<robot>";
    std::string s = fmt::format("<{}", e->Name());
    if (const char* n = e->Attribute("name")) s += fmt::format(" name=\"{}\"", text::printable(n));
    if (const char* n = e->Attribute("link")) s += fmt::format(" link=\"{}\"", text::printable(n));
    s += ">";
    const auto* p = e->Parent() ? e->Parent()->ToElement() : nullptr;
    if (p && std::string_view(p->Name()) != "robot" && !e->Attribute("name")) {
      const XMLElement* owner = p;
      while (owner && !owner->Attribute("name")) owner = owner->Parent() ? owner->Parent()->ToElement() : nullptr;
      if (owner) s += fmt::format(" in <{} name=\"{}\">", owner->Name(), text::printable(owner->Attribute("name")));
    }
    return s;
  }

  const char* required_attribute(const XMLElement* e, const char* name, std::string_view what) const {
    const char* v = e->Attribute(name);
    if (!v) fail(e, fmt::format("missing attribute {}=\"...\" ({})", name, what));
    return v;
  }

  double number(const XMLElement* e, const char* attr, std::string_view text, std::string_view what) const {
    const std::string s(text);
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    while (end && (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r')) ++end;
    if (s.empty() || end == s.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(v))
      fail(e, fmt::format("{}=\"{}\" is not a finite number ({})", attr, text::printable(s), what));
    return v;
  }

  double number_attribute(const XMLElement* e, const char* attr, std::string_view what,
                          std::optional<double> fallback = {}) const {
    const char* v = e->Attribute(attr);
    if (!v) {
      if (fallback) return *fallback;
      fail(e, fmt::format("missing attribute {}=\"...\" ({})", attr, what));
    }
    return number(e, attr, v, what);
  }

  // "x y z": three numbers separated by white space.
  Vec3 triple(const XMLElement* e, const char* attr, std::string_view what, const Vec3& fallback) const {
    const char* v = e->Attribute(attr);
    if (!v) return fallback;
    std::vector<std::string> words;
    std::string word;
    for (const char* c = v;; ++c) {
      if (*c == '\0' || *c == ' ' || *c == '\t' || *c == '\n' || *c == '\r') {
        if (!word.empty()) words.push_back(word);
        word.clear();
        if (*c == '\0') break;
      } else {
        word += *c;
      }
    }
    if (words.size() != 3)
      fail(e, fmt::format("{}=\"{}\" must be three numbers separated by spaces ({}), e.g. {}=\"0 0 1\"", attr,
                          text::printable(v), what, attr));
    Vec3 out;
    for (int k = 0; k < 3; ++k) out[k] = number(e, attr, words[static_cast<std::size_t>(k)], what);
    return out;
  }

  // <origin xyz rpy> (optional: identity).
  UrdfFrame origin(const XMLElement* parent) const {
    UrdfFrame f;
    const XMLElement* o = parent->FirstChildElement("origin");
    if (!o) return f;
    f.t = triple(o, "xyz", "m, the frame's position in its parent frame", Vec3::Zero());
    if (f.t.norm() > kMaxLength)
      fail(o, fmt::format("xyz is {:g} m from the parent frame; at most {:g} m is accepted (check the units)",
                          f.t.norm(), kMaxLength));
    const Vec3 rpy = triple(o, "rpy", "rad: roll about x, pitch about y, yaw about z, fixed axes", Vec3::Zero());
    f.R = so3::axis_rotation(2, rpy[2]) * so3::axis_rotation(1, rpy[1]) * so3::axis_rotation(0, rpy[0]);
    return f;
  }

  UrdfInertial inertial(const XMLElement* e) const {
    UrdfInertial in;
    in.line = e->GetLineNum();
    in.origin = origin(e);
    const XMLElement* m = e->FirstChildElement("mass");
    if (!m) fail(e, "missing <mass value=\"...\"/> (kg)");
    in.mass = number_attribute(m, "value", "kg, >= 0");
    if (!(in.mass >= 0.0 && in.mass <= kMaxUrdfMass))
      fail(m, fmt::format("value=\"{}\": a mass must lie in [0, {:g}] kg", in.mass, kMaxUrdfMass));
    const XMLElement* i = e->FirstChildElement("inertia");
    if (!i)
      fail(e, "missing <inertia ixx=\"..\" ixy=\"..\" ixz=\"..\" iyy=\"..\" iyz=\"..\" izz=\"..\"/> (kg m^2, about "
              "the centre of mass, in the axes of <inertial><origin rpy>)");
    const char* what = "kg m^2";
    const double ixx = number_attribute(i, "ixx", what), iyy = number_attribute(i, "iyy", what),
                 izz = number_attribute(i, "izz", what);
    const double ixy = number_attribute(i, "ixy", what, 0.0), ixz = number_attribute(i, "ixz", what, 0.0),
                 iyz = number_attribute(i, "iyz", what, 0.0);
    in.inertia << ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz;
    const double scale = in.inertia.cwiseAbs().maxCoeff();
    if (scale > kMaxInertia)
      fail(i, fmt::format("an inertia entry of {:g} kg m^2 is beyond {:g} (check the units)", scale, kMaxInertia));
    if (in.mass == 0.0 && scale > 0.0)
      fail(i, "a massless link cannot have inertia: give <mass> a positive value, or all six entries 0");
    // Physically possible: positive semi-definite, principal moments obeying
    // the triangle inequality J1 <= J2 + J3.
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(in.inertia);
    const Vec3 J = eig.eigenvalues();
    const double slack = kInertiaSlack * std::max(scale, 1e-300);
    if (J[0] < -slack || J[2] > J[0] + J[1] + slack)
      fail(i, fmt::format("no mass distribution has this inertia: its principal moments are {:.6g}, {:.6g}, "
                          "{:.6g} kg m^2, and each must be >= 0 and at most the sum of the other two (the "
                          "off-diagonal entries are products of inertia, +integral of x y dm: URDF's sign)",
                          J[0], J[1], J[2]));
    return in;
  }

  std::optional<JointLimits> limits(const XMLElement* j, UrdfJointType type) const {
    const XMLElement* l = j->FirstChildElement("limit");
    const bool needs = type == UrdfJointType::Revolute || type == UrdfJointType::Prismatic;
    if (!l) {
      if (needs)
        fail(j, fmt::format("a {} joint needs <limit lower=\"..\" upper=\"..\" effort=\"..\" velocity=\"..\"/> "
                            "(URDF requires it; rigidae keeps the limits as data and does not enforce them; for "
                            "a joint without stops use type=\"continuous\")",
                            type == UrdfJointType::Revolute ? "revolute" : "prismatic"));
      return std::nullopt;
    }
    if (type == UrdfJointType::Fixed || type == UrdfJointType::Floating) return std::nullopt;
    JointLimits lim;
    const char* unit = type == UrdfJointType::Prismatic ? "m" : "rad";
    if (type != UrdfJointType::Continuous) {
      lim.lower = number_attribute(l, "lower", unit, 0.0);
      lim.upper = number_attribute(l, "upper", unit, 0.0);
      if (*lim.lower > *lim.upper)
        fail(l, fmt::format("lower=\"{}\" is above upper=\"{}\"; give lower <= upper", *lim.lower, *lim.upper));
    }
    lim.effort = number_attribute(l, "effort", type == UrdfJointType::Prismatic ? "N, >= 0" : "N m, >= 0");
    lim.velocity = number_attribute(l, "velocity", type == UrdfJointType::Prismatic ? "m/s, >= 0" : "rad/s, >= 0");
    if (*lim.effort < 0.0) fail(l, fmt::format("effort=\"{}\" must be >= 0", *lim.effort));
    if (*lim.velocity < 0.0) fail(l, fmt::format("velocity=\"{}\" must be >= 0", *lim.velocity));
    return lim;
  }

  UrdfJoint joint(const XMLElement* e) const {
    UrdfJoint j;
    j.line = e->GetLineNum();
    j.name = required_attribute(e, "name", "the joint's name");
    const std::string type = required_attribute(e, "type", "revolute, continuous, prismatic, fixed or floating");
    int k = -1;
    for (std::size_t i = 0; i < kJointTypes.size(); ++i)
      if (type == kJointTypes[i]) k = static_cast<int>(i);
    if (k == 5)
      fail(e, "type=\"planar\" is not supported: rigidae has no planar joint (use two prismatic joints and a "
              "revolute one through massive intermediate links, or a TOML scene)");
    if (k < 0) {
      std::string msg = fmt::format("type=\"{}\" is not a URDF joint type", text::printable(type));
      const std::array<std::string_view, 5> known{kJointTypes[0], kJointTypes[1], kJointTypes[2], kJointTypes[3],
                                                  kJointTypes[4]};
      if (auto best = text::closest(type, known)) msg += fmt::format("; did you mean \"{}\"?", *best);
      fail(e, msg + " (valid: revolute, continuous, prismatic, fixed, floating)");
    }
    j.type = static_cast<UrdfJointType>(k);
    const XMLElement* p = e->FirstChildElement("parent");
    if (!p) fail(e, "missing <parent link=\"...\"/> (the link this joint hangs from)");
    j.parent = required_attribute(p, "link", "the parent link's name");
    const XMLElement* c = e->FirstChildElement("child");
    if (!c) fail(e, "missing <child link=\"...\"/> (the link this joint moves)");
    j.child = required_attribute(c, "link", "the child link's name");
    if (j.parent == j.child) fail(c, fmt::format("the joint joins link \"{}\" to itself", text::printable(j.child)));
    j.origin = origin(e);
    if (const XMLElement* a = e->FirstChildElement("axis")) {
      const Vec3 axis = triple(a, "xyz", "the joint axis in the joint frame", Vec3::UnitX());
      if (!(axis.norm() > 0.0)) fail(a, "xyz=\"0 0 0\" is no direction: give the joint axis, e.g. xyz=\"0 0 1\"");
      j.axis = axis.normalized();
    }
    j.limits = limits(e, j.type);
    if (const XMLElement* d = e->FirstChildElement("dynamics")) {
      const double damping = number_attribute(d, "damping", "N m s/rad or N s/m, >= 0", 0.0);
      const double friction = number_attribute(d, "friction", "N m or N, >= 0", 0.0);
      if (damping < 0.0) fail(d, fmt::format("damping=\"{}\" must be >= 0", damping));
      if (friction != 0.0)
        fail(d, fmt::format("friction=\"{}\": rigidae models no joint friction; remove it (or set 0)", friction));
      const bool turns = j.type == UrdfJointType::Revolute || j.type == UrdfJointType::Continuous;
      if (damping != 0.0 && !turns)
        fail(d, fmt::format("damping=\"{}\" on a {} joint: rigidae has viscous damping in revolute and continuous "
                            "joints only; remove it (or set 0)",
                            damping, type));
      j.damping = damping;
    }
    if (const XMLElement* m = e->FirstChildElement("mimic"))
      fail(m, "<mimic> couples joints, which rigidae does not model; remove it (the joint then moves freely)");
    static constexpr std::array<std::string_view, 9> kKnown{"origin", "parent",      "child",  "axis",
                                                            "limit",  "dynamics",    "mimic",  "calibration",
                                                            "safety_controller"};
    for (const XMLElement* x = e->FirstChildElement(); x; x = x->NextSiblingElement())
      if (std::find(kKnown.begin(), kKnown.end(), std::string_view(x->Name())) == kKnown.end())
        warn(x, fmt::format("unknown element in a joint, ignored (known: {})", text::quoted_list(kKnown)));
    return j;
  }

  UrdfLink link(const XMLElement* e) const {
    UrdfLink l;
    l.line = e->GetLineNum();
    l.name = required_attribute(e, "name", "the link's name");
    const XMLElement* in = e->FirstChildElement("inertial");
    if (in) {
      if (in->NextSiblingElement("inertial")) fail(in->NextSiblingElement("inertial"), "a link has at most one <inertial>");
      l.inertial = inertial(in);
    }
    return l;
  }

  UrdfModel read(const std::string& text) const {
    tinyxml2::XMLDocument doc;
    if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS)
      throw InputError(fmt::format("{}:{}: error: not well-formed XML: {} (a URDF file is XML with a <robot> root)",
                                   file_, std::max(doc.ErrorLineNum(), 1), text::printable(doc.ErrorStr(), 200)));
    const XMLElement* robot = doc.RootElement();
    if (!robot || std::string_view(robot->Name()) != "robot")
      throw InputError(fmt::format("{}:{}: error: the root element is <{}>, not <robot>: a URDF file describes one "
                                   "<robot> of <link> and <joint> elements",
                                   file_, robot ? robot->GetLineNum() : 1, robot ? robot->Name() : ""));
    UrdfModel m;
    m.source = file_;
    if (const char* n = robot->Attribute("name")) m.name = n;
    std::map<std::string, int> link_line, joint_line;
    for (const XMLElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string_view tag = e->Name();
      if (tag == "link") {
        UrdfLink l = link(e);
        if (auto [it, fresh] = link_line.emplace(l.name, l.line); !fresh)
          fail(e, fmt::format("a second link named \"{}\" (the first is on line {}); link names must be unique",
                              text::printable(l.name), it->second));
        m.links.push_back(std::move(l));
      } else if (tag == "joint") {
        UrdfJoint j = joint(e);
        if (auto [it, fresh] = joint_line.emplace(j.name, j.line); !fresh)
          fail(e, fmt::format("a second joint named \"{}\" (the first is on line {}); joint names must be unique",
                              text::printable(j.name), it->second));
        m.joints.push_back(std::move(j));
      }
      // <material>, <transmission>, <gazebo>, ...: no effect on the motion.
    }
    if (m.links.empty())
      throw InputError(fmt::format("{}:{}: error: <robot> has no <link>: nothing to simulate", file_,
                                   robot->GetLineNum()));
    return m;
  }

 private:
  std::string file_;
};

}  // namespace

UrdfModel parse_urdf(const std::string& text, const std::string& source_name) {
  return Reader(source_name).read(text);
}

}  // namespace rigidae::io
