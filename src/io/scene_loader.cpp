// Scene files: TOML, schema_version 1. The format is documented key by key in
// docs/scene_format.md; this file is its only implementation.
//
// Every problem is reported as an InputError whose message starts with
// "FILE:LINE:COL: error: " (the position of the offending key or value, or of
// the enclosing table when a key is missing) and says what would be valid.
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/schemes/scheme.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iostream>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "rigidae/core/error.hpp"
#include "rigidae/solver/integrators.hpp"
#include "rigidae/exact/exact_solution.hpp"
#include "rigidae/so3/euler_sequence.hpp"
#include "rigidae/so3/rotation.hpp"
#include "toml_reader.hpp"

namespace rigidae::io {
namespace {

// ---------------------------------------------------------------------------
// The schema: allowed keys of every table, and the value lists.
// ---------------------------------------------------------------------------


constexpr int kSchemaVersion = 1;

constexpr std::array<std::string_view, 11> kRootKeys{
    "schema_version", "name", "description", "body", "support",
    "gravity", "initial", "time", "formulation", "solver", "reference"};
constexpr std::array<std::string_view, 4> kBodyKeys{"mass", "inertia_principal", "inertia",
                                                    "center_of_mass"};
constexpr std::array<std::string_view, 1> kSupportKeys{"type"};
constexpr std::array<std::string_view, 1> kGravityKeys{"acceleration"};
constexpr std::array<std::string_view, 6> kInitialKeys{
    "quaternion", "euler", "matrix", "axis_angle", "angular_velocity", "angular_velocity_frame"};
constexpr std::array<std::string_view, 3> kInitialEulerKeys{"sequence", "convention", "angles"};
constexpr std::array<std::string_view, 2> kAxisAngleKeys{"axis", "angle"};
constexpr std::array<std::string_view, 3> kTimeKeys{"start", "end", "output_step"};
constexpr std::array<std::string_view, 6> kFormulationKeys{"coordinates", "equations", "scheme",
                                                           "euler_angles", "baumgarte", "projection"};
constexpr std::array<std::string_view, 4> kEulerAnglesKeys{"sequence", "convention", "switching",
                                                           "switch_threshold"};
constexpr std::array<std::string_view, 2> kBaumgarteKeys{"a", "b"};
constexpr std::array<std::string_view, 2> kProjectionKeys{"when", "threshold"};
constexpr std::array<std::string_view, 9> kSolverKeys{"rtol",          "atol",       "max_steps",
                                                      "max_order",     "initial_step", "jacobian",
                                                      "linear_solver", "integrator", "erk_method"};

constexpr std::array<std::string_view, 4> kOrientationForms{"quaternion", "euler", "matrix",
                                                            "axis_angle"};

// Used to point a key written in the wrong table to the right one.
const std::array<SectionKeys, 13> kAllSections{{
    {"", kRootKeys},
    {"body", kBodyKeys},
    {"support", kSupportKeys},
    {"gravity", kGravityKeys},
    {"initial", kInitialKeys},
    {"initial.euler", kInitialEulerKeys},
    {"initial.axis_angle", kAxisAngleKeys},
    {"time", kTimeKeys},
    {"formulation", kFormulationKeys},
    {"formulation.euler_angles", kEulerAnglesKeys},
    {"formulation.baumgarte", kBaumgarteKeys},
    {"formulation.projection", kProjectionKeys},
    {"solver", kSolverKeys},
}};

// Magnitudes beyond these are taken as input mistakes (wrong units, typos).
constexpr double kMaxMass = 1e9;                 // kg
constexpr double kMaxAngularVelocity = 1e6;      // rad/s
constexpr double kMaxGravity = 1e4;              // m/s^2
constexpr double kMaxCenterOfMass = 1e6;         // m
constexpr double kMaxBaumgarteGain = 1e8;        // 1/s
constexpr double kMinRtol = kMinRelativeTolerance;  // see scene.hpp
constexpr double kMaxTime = kMaxTimeMagnitude;   // s, |time.start| and |time.end|
constexpr std::size_t kMaxNameBytes = 100;       // the name becomes part of the default output folder
constexpr std::size_t kMaxSceneBytes = 1 << 20;  // a scene is a few hundred bytes; a bigger file is a mistake

constexpr double kInertiaSymmetryTol = 1e-12;    // relative
constexpr double kTriangleTol = 1e-12;           // relative to the trace
constexpr double kUnitTolError = 1e-6;           // | |q| - 1 |, ||R^T R - I||_F
constexpr double kUnitTolSilent = 1e-12;         // below: fixed without a warning


std::string fmt_vec(const Vec3& v) { return fmt::format("({}, {}, {})", v[0], v[1], v[2]); }
// Computed values (not the user's digits): round-off shown as such would only distract.
std::string fmt_vec6(const Vec3& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v[0], v[1], v[2]); }

// ---------------------------------------------------------------------------
// Sections
// ---------------------------------------------------------------------------

// Where the inertia came from, for messages about it once the support is known.
struct InertiaSource {
  const toml::node* node = nullptr;
  const char* name = "";
};

InertiaSource read_body(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table& body = r.required_table(root, "", "body");
  r.check_keys(body, "body", kBodyKeys, kAllSections);

  const toml::node& mass_node = r.required(body, "body", "mass", "kg, > 0");
  const double mass = r.number(mass_node, "body.mass");
  if (!(mass > 0.0) || mass >= kMaxMass)
    r.fail(mass_node, fmt::format("'body.mass' must be > 0 and < {:g} kg, got {}", kMaxMass, mass));
  scene.body.mass = mass;

  const toml::node* principal = body.get("inertia_principal");
  const toml::node* full = body.get("inertia");
  if (principal && full) {
    const toml::node& later = before(principal->source().begin, full->source().begin) ? *full : *principal;
    r.fail(later, "give either 'body.inertia_principal' or 'body.inertia', not both");
  }
  if (!principal && !full)
    r.fail(body.source(),
           "missing the inertia in [body]: give 'inertia_principal = [J1, J2, J3]' (kg m^2, "
           "principal moments about the centre of mass along the body axes) or "
           "'inertia = [[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]]'");

  Vec3 moments;
  const toml::node* inertia_node = principal ? principal : full;
  const char* inertia_name = principal ? "body.inertia_principal" : "body.inertia";
  if (principal) {
    moments = r.vec3(*principal, inertia_name);
    const toml::array& a = *principal->as_array();
    for (int i = 0; i < 3; ++i)
      if (!(moments[i] > 0.0))
        r.fail(*a.get(i), fmt::format("'{}[{}]' must be > 0 (a principal moment of inertia), got {}",
                                      inertia_name, i, moments[i]));
    scene.body.inertia_com = moments.asDiagonal();
  } else {
    std::array<std::array<const toml::node*, 3>, 3> el{};
    Mat3 I = r.mat3(*full, inertia_name, &el);
    const double scale = I.cwiseAbs().maxCoeff();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < i; ++j) {
        const double asym = std::abs(I(i, j) - I(j, i));
        if (asym > kInertiaSymmetryTol * scale)
          r.fail(*el[i][j],
                 fmt::format("'body.inertia' must be symmetric: element [{}][{}] = {} differs from "
                             "[{}][{}] = {} (relative difference {:.3g} > {:g})",
                             i, j, I(i, j), j, i, I(j, i), scale > 0 ? asym / scale : 0.0,
                             kInertiaSymmetryTol));
      }
    }
    I = 0.5 * (I + I.transpose()).eval();
    Eigen::SelfAdjointEigenSolver<Mat3> eig(I);
    moments = eig.eigenvalues();
    if (!(moments.minCoeff() > 0.0))
      r.fail(*full, fmt::format("'body.inertia' must be positive definite; its principal moments "
                                "(eigenvalues) are {}",
                                fmt_vec6(moments)));
    scene.body.inertia_com = I;
  }
  if (const toml::node* c = body.get("center_of_mass")) {
    const Vec3 com = r.vec3(*c, "body.center_of_mass");
    if (com.norm() > kMaxCenterOfMass)
      r.fail(*c, fmt::format("'body.center_of_mass' is {} m from the body origin; it must be at "
                             "most {:g} m (check the units: metres)",
                             com.norm(), kMaxCenterOfMass));
    scene.body.com_B = com;
  }
  return {inertia_node, inertia_name};
}

std::string fmt_moments(const Vec3& J) { return fmt::format("J1 = {}, J2 = {}, J3 = {}", J[0], J[1], J[2]); }

// The triangle inequality of the principal moments. J_i <= J_j + J_k holds for
// every mass distribution; equality means all the mass lies in one plane
// through the reference point, and then the second moment of mass
// (tr(J)/2 I - J) is singular -- the rotation is not determined by the motion
// of the material points, and the linear-coordinate formulation has a
// singular mass matrix. The reference point is the one the body rotates
// about: the fixed point of a top, the centre of mass of a free body.
void check_triangle_inequality(const TomlReader& r, const InertiaSource& src, const Scene& scene) {
  const Mat3& Ic = scene.body.inertia_com;
  const Vec3 Jc = Eigen::SelfAdjointEigenSolver<Mat3>(Ic).eigenvalues();
  const double trace_c = Jc.sum();
  for (int i = 0; i < 3; ++i) {
    const double others = trace_c - Jc[i];
    if (Jc[i] > others + kTriangleTol * trace_c)
      r.fail(*src.node,
             fmt::format("'{}': the principal moments about the centre of mass ({}) violate the "
                         "triangle inequality: J{} = {} exceeds the sum of the other two ({}); no "
                         "mass distribution has these moments (valid: J1 < J2 + J3, J2 < J1 + J3, "
                         "J3 < J1 + J2)",
                         src.name, fmt_moments(Jc), i + 1, Jc[i], others));
  }

  const bool fixed = scene.support == Support::FixedPoint;
  const Vec3& c = scene.body.com_B;
  const Mat3 I = fixed ? Mat3(Ic + scene.body.mass * (c.squaredNorm() * Mat3::Identity() - c * c.transpose()))
                       : Ic;
  const Vec3 J = Eigen::SelfAdjointEigenSolver<Mat3>(I).eigenvalues();
  const double trace = J.sum();
  const char* about = fixed ? "about the fixed point" : "about the centre of mass";
  for (int i = 0; i < 3; ++i) {
    const double others = trace - J[i];
    if (J[i] >= others - kTriangleTol * trace)
      r.fail(*src.node,
             fmt::format("'{}': the principal moments {} ({}) break the strict triangle "
                         "inequality: J{} = {} is not less than the sum of the other two ({}), so "
                         "all the mass lies in one plane through {} -- a body with no thickness "
                         "is not a rigid body here (valid: J1 < J2 + J3, J2 < J1 + J3 and "
                         "J3 < J1 + J2, with a relative margin of {:g}){}",
                         src.name, about, fmt_moments(J), i + 1, J[i], others,
                         fixed ? "the fixed point" : "the centre of mass", kTriangleTol,
                         fixed && c.squaredNorm() > 0.0
                             ? fmt::format("; moments about the fixed point are J_com + m(|c|^2 I "
                                           "- c c^T) with the centre of mass c = {}",
                                           fmt_vec(c))
                             : std::string()));
  }
}

void read_support(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table* sup = r.optional_table(root, "", "support");
  if (!sup) return;
  r.check_keys(*sup, "support", kSupportKeys, kAllSections);
  if (const toml::node* t = sup->get("type")) {
    constexpr std::array<std::string_view, 2> opts{"fixed_point", "free"};
    scene.support = r.choice(*t, "support.type", opts) == 0 ? Support::FixedPoint : Support::Free;
  }
}

void read_gravity(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table* g = r.optional_table(root, "", "gravity");
  if (!g) return;
  r.check_keys(*g, "gravity", kGravityKeys, kAllSections);
  if (const toml::node* a = g->get("acceleration")) {
    const Vec3 acc = r.vec3(*a, "gravity.acceleration");
    if (acc.norm() > kMaxGravity)
      r.fail(*a, fmt::format("|gravity.acceleration| = {} m/s^2 is too large; it must be at most "
                             "{:g} m/s^2",
                             acc.norm(), kMaxGravity));
    scene.gravity_W = acc;
  }
}

bool read_convention(const TomlReader& r, const toml::table& tbl, std::string_view table) {
  const toml::node* c = tbl.get("convention");
  if (!c) return false;
  constexpr std::array<std::string_view, 2> opts{"intrinsic", "extrinsic"};
  return r.choice(*c, join_key(table, "convention"), opts) == 1;
}

so3::EulerSequence read_sequence(const TomlReader& r, const toml::node& n, std::string_view name,
                                 bool extrinsic, Vec3* angles) {
  const std::string letters = r.string(n, name);
  if (letters.size() != 3)
    r.fail(n, fmt::format("'{}' = \"{}\" is not an Euler sequence: give three axis letters from x, y, z with "
                          "consecutive letters distinct, e.g. \"zxz\" or \"zyx\"",
                          name, printable(letters)));
  try {
    return so3::parse_euler_sequence(letters, extrinsic, angles);
  } catch (const std::invalid_argument& e) {
    r.fail(n, fmt::format("'{}' = \"{}\": {}", name, printable(letters), printable(e.what(), 1000)));
  }
}

Mat3 read_orientation(const TomlReader& r, const toml::table& init) {
  const toml::node* form = nullptr;
  std::string_view form_name;
  for (auto name : kOrientationForms) {
    const toml::node* n = init.get(name);
    if (!n) continue;
    if (form) {
      const bool n_later = before(form->source().begin, n->source().begin);
      const toml::node& later = n_later ? *n : *form;
      r.fail(later, fmt::format("[initial] has several orientations ('{}' and '{}'); give exactly "
                                "one of {}",
                                n_later ? form_name : name, n_later ? name : form_name,
                                quoted_list(kOrientationForms)));
    }
    form = n;
    form_name = name;
  }
  if (!form)
    r.fail(init.source(), fmt::format("[initial] needs an orientation: give exactly one of {} "
                                      "(e.g. quaternion = [1.0, 0.0, 0.0, 0.0] for the identity)",
                                      quoted_list(kOrientationForms)));

  if (form_name == "quaternion") {
    const Vec4 q = r.vector<4>(*form, "initial.quaternion");
    const double n = q.norm();
    if (n == 0.0)
      r.fail(*form, "'initial.quaternion' has zero norm; give a unit quaternion (w, x, y, z), "
                    "scalar first, e.g. [1.0, 0.0, 0.0, 0.0] for the identity");
    const double dev = std::abs(n - 1.0);
    if (dev > kUnitTolError)
      r.fail(*form, fmt::format("'initial.quaternion' has norm {} (| |q| - 1 | = {:.3g} > {:g}); "
                                "normalise it (a unit quaternion is expected, scalar first)",
                                n, dev, kUnitTolError));
    if (dev > kUnitTolSilent)
      r.warn(*form, fmt::format("'initial.quaternion' has norm {} (| |q| - 1 | = {:.3g}); "
                                "normalised",
                                n, dev));
    return so3::quaternion_to_matrix(q / n);
  }

  if (form_name == "matrix") {
    const Mat3 M = r.mat3(*form, "initial.matrix");
    const double dev = (M.transpose() * M - Mat3::Identity()).norm();
    if (dev > kUnitTolError)
      r.fail(*form, fmt::format("'initial.matrix' is not orthogonal: ||R^T R - I||_F = {:.3g} > "
                                "{:g}; give the rotation matrix R_WB (rows, body to world) "
                                "to at least 7 significant digits",
                                dev, kUnitTolError));
    if (M.determinant() < 0.0)
      r.fail(*form, "'initial.matrix' has determinant -1: it is a reflection, not a rotation "
                    "(flip the sign of one row or column)");
    if (dev > kUnitTolSilent)
      r.warn(*form, fmt::format("'initial.matrix' deviates from a rotation by ||R^T R - I||_F = "
                                "{:.3g}; replaced by the nearest rotation",
                                dev));
    return so3::nearest_rotation(M);
  }

  if (form_name == "euler") {
    if (!form->is_table())
      r.fail(*form, fmt::format("'initial.euler' must be a table such as {{ sequence = \"zxz\", "
                                "convention = \"intrinsic\", angles = [0.1, 0.2, 0.3] }}, not {}",
                                type_name(*form)));
    const toml::table& e = *form->as_table();
    r.check_keys(e, "initial.euler", kInitialEulerKeys, kAllSections);
    const toml::node& seq_node =
        r.required(e, "initial.euler", "sequence", "three axis letters such as \"zxz\" or \"zyx\"");
    const toml::node& angles_node =
        r.required(e, "initial.euler", "angles", "[a, b, c] in rad, in the order of the sequence");
    const bool extrinsic = read_convention(r, e, "initial.euler");
    Vec3 angles = r.vec3(angles_node, "initial.euler.angles");
    const so3::EulerSequence seq = read_sequence(r, seq_node, "initial.euler.sequence", extrinsic, &angles);
    return so3::euler_to_matrix(seq, angles);
  }

  // axis_angle
  if (!form->is_table())
    r.fail(*form, fmt::format("'initial.axis_angle' must be a table such as {{ axis = [0.0, 0.0, "
                              "1.0], angle = 0.5 }}, not {}",
                              type_name(*form)));
  const toml::table& aa = *form->as_table();
  r.check_keys(aa, "initial.axis_angle", kAxisAngleKeys, kAllSections);
  const toml::node& axis_node =
      r.required(aa, "initial.axis_angle", "axis", "[x, y, z], any non-zero length");
  const toml::node& angle_node = r.required(aa, "initial.axis_angle", "angle", "rad");
  const Vec3 axis = r.vec3(axis_node, "initial.axis_angle.axis");
  const double angle = r.number(angle_node, "initial.axis_angle.angle");
  const double len = axis.norm();
  if (!(len > 0.0) || !std::isfinite(len))
    r.fail(axis_node, "'initial.axis_angle.axis' must be a non-zero vector (it is normalised by "
                      "the loader)");
  return so3::axis_angle_to_matrix(axis / len, angle);
}

void read_initial(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table& init = r.required_table(root, "", "initial");
  r.check_keys(init, "initial", kInitialKeys, kAllSections);
  scene.R0_WB = read_orientation(r, init);

  const toml::node& w_node =
      r.required(init, "initial", "angular_velocity", "[wx, wy, wz] in rad/s");
  const Vec3 w = r.vec3(w_node, "initial.angular_velocity");
  if (w.norm() > kMaxAngularVelocity)
    r.fail(w_node, fmt::format("|initial.angular_velocity| = {} rad/s is too large; it must be at "
                               "most {:g} rad/s (check the units: rad/s, not rpm or deg/s)",
                               w.norm(), kMaxAngularVelocity));
  bool space = false;
  if (const toml::node* f = init.get("angular_velocity_frame")) {
    constexpr std::array<std::string_view, 2> opts{"body", "space"};
    space = r.choice(*f, "initial.angular_velocity_frame", opts) == 1;
  }
  scene.omega0_B = space ? Vec3(scene.R0_WB.transpose() * w) : w;
}

void read_time(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table& t = r.required_table(root, "", "time");
  r.check_keys(t, "time", kTimeKeys, kAllSections);
  double start = 0.0;
  const auto check_magnitude = [&](const toml::node& n, std::string_view name, double x) {
    if (std::abs(x) > kMaxTime)
      r.fail(n, fmt::format("'{}' = {} s is too large; times must lie within +-{:g} s", name, x, kMaxTime));
  };
  if (const toml::node* s = t.get("start")) {
    start = r.number(*s, "time.start");
    check_magnitude(*s, "time.start", start);
  }
  const toml::node& end_node = r.required(t, "time", "end", "s, > start");
  const double end = r.number(end_node, "time.end");
  check_magnitude(end_node, "time.end", end);
  if (!(end > start))
    r.fail(end_node, fmt::format("'time.end' = {} must be greater than 'time.start' = {}", end, start));
  const double span = end - start;
  double step = span / 100.0;
  if (const toml::node* o = t.get("output_step")) {
    step = r.number(*o, "time.output_step");
    if (!(step > 0.0) || step > span)
      r.fail(*o, fmt::format("'time.output_step' = {} must be > 0 and <= end - start = {} s", step, span));
    if (span / step > kMaxOutputIntervals)
      r.fail(*o, fmt::format("'time.output_step' = {} gives {:.3g} output intervals over {} s; at "
                             "most {:g} are allowed",
                             step, span / step, span, kMaxOutputIntervals));
  }
  scene.time.start = start;
  scene.time.end = end;
  scene.time.output_step = step;
}

void read_euler_charts(const TomlReader& r, const toml::table& f, EulerChartSpec& euler) {
  const toml::table* ea = r.optional_table(f, "formulation", "euler_angles");
  if (!ea) return;
  r.check_keys(*ea, "formulation.euler_angles", kEulerAnglesKeys, kAllSections);
  const bool extrinsic = read_convention(r, *ea, "formulation.euler_angles");
  if (const toml::node* s = ea->get("sequence")) {
    const std::string letters = r.string(*s, "formulation.euler_angles.sequence");
    if (letters == "auto")
      euler.sequence.reset();
    else
      euler.sequence = read_sequence(r, *s, "formulation.euler_angles.sequence", extrinsic, nullptr);
  }
  if (const toml::node* s = ea->get("switching"))
    euler.switching = r.boolean(*s, "formulation.euler_angles.switching");
  if (const toml::node* s = ea->get("switch_threshold")) {
    const double th = r.number(*s, "formulation.euler_angles.switch_threshold");
    if (!(th > 0.0 && th < 1.0))
      r.fail(*s, fmt::format("'formulation.euler_angles.switch_threshold' = {} must lie in (0, 1) "
                             "(a margin |sin b| or |cos b|)",
                             th));
    euler.switch_threshold = th;
  }
}

void read_baumgarte(const TomlReader& r, const toml::table& f, BaumgarteGains& gains) {
  const toml::table* b = r.optional_table(f, "formulation", "baumgarte");
  if (!b) return;
  r.check_keys(*b, "formulation.baumgarte", kBaumgarteKeys, kAllSections);
  for (const char* key : {"a", "b"}) {
    const toml::node* n = b->get(key);
    if (!n) continue;
    const std::string name = fmt::format("formulation.baumgarte.{}", key);
    const double v = r.number(*n, name);
    if (!(v >= 0.0 && v <= kMaxBaumgarteGain))
      r.fail(*n, fmt::format("'{}' = {} must lie in [0, {:g}] (1/s; a rate of the constraint feedback)", name, v,
                             kMaxBaumgarteGain));
    (key[0] == 'a' ? gains.a : gains.b) = v;
  }
}

void read_projection(const TomlReader& r, const toml::table& f, ProjectionSpec& spec) {
  const toml::table* p = r.optional_table(f, "formulation", "projection");
  if (!p) return;
  r.check_keys(*p, "formulation.projection", kProjectionKeys, kAllSections);
  if (const toml::node* w = p->get("when")) {
    constexpr std::array<std::string_view, 2> opts{"threshold", "every_step"};
    spec.every_step = r.choice(*w, "formulation.projection.when", opts) == 1;
  }
  if (const toml::node* n = p->get("threshold")) {
    const double v = r.number(*n, "formulation.projection.threshold");
    if (!(v > 0.0 && v < 1.0))
      r.fail(*n, fmt::format("'formulation.projection.threshold' = {} must lie in (0, 1) (a drift |Phi|, e.g. 1e-8)",
                             v));
    spec.threshold = v;
  }
}

void read_formulation(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table* f = r.optional_table(root, "", "formulation");
  if (!f) return;
  r.check_keys(*f, "formulation", kFormulationKeys, kAllSections);
  Formulation& form = scene.formulation;
  if (const toml::node* c = f->get("coordinates")) {
    constexpr std::array<std::string_view, 3> opts{"euler", "quaternion", "linear"};
    constexpr std::array<Coordinates, 3> vals{Coordinates::EulerAngles, Coordinates::Quaternion,
                                              Coordinates::Linear};
    form.coordinates = vals[r.choice(*c, "formulation.coordinates", opts)];
  }
  if (const toml::node* e = f->get("equations")) {
    constexpr std::array<std::string_view, 2> opts{"lagrange", "euler"};
    form.equations = r.choice(*e, "formulation.equations", opts) == 0 ? Equations::Lagrange
                                                                      : Equations::Euler;
  }
  if (const toml::node* s = f->get("scheme")) {
    // The scheme registry is the one list of valid names.
    const std::vector<std::string> names = scheme_names();
    const std::vector<std::string_view> views(names.begin(), names.end());
    form.scheme = names[r.choice(*s, "formulation.scheme", views)];
  }

  read_euler_charts(r, *f, form.euler);
  read_baumgarte(r, *f, form.baumgarte);
  read_projection(r, *f, form.projection);
}

void read_solver(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::table* s = r.optional_table(root, "", "solver");
  if (!s) return;
  r.check_keys(*s, "solver", kSolverKeys, kAllSections);
  SolverSettings& sol = scene.solver;
  if (const toml::node* n = s->get("rtol")) {
    const double v = r.number(*n, "solver.rtol");
    if (!(v >= kMinRtol && v < 1.0))
      r.fail(*n, fmt::format("'solver.rtol' = {} must lie in [{:g}, 1), e.g. 1e-8 (below {:g} round-off in "
                             "double precision exceeds the tolerance and the step size collapses)",
                             v, kMinRtol, kMinRtol));
    sol.rtol = v;
  }
  if (const toml::node* n = s->get("atol")) {
    const double v = r.number(*n, "solver.atol");
    if (!(v >= kMinAbsoluteTolerance && v < 1.0))
      r.fail(*n, fmt::format("'solver.atol' = {} must lie in [{:g}, 1), e.g. 1e-8 (below {:g} IDA's weighted "
                             "norms overflow)",
                             v, kMinAbsoluteTolerance, kMinAbsoluteTolerance));
    sol.atol = v;
  }
  if (const toml::node* n = s->get("max_steps")) {
    const long long v = r.integer(*n, "solver.max_steps");
    if (v < 1) r.fail(*n, fmt::format("'solver.max_steps' = {} must be an integer >= 1", v));
    sol.max_steps = static_cast<long>(v);
  }
  if (const toml::node* n = s->get("max_order")) {
    const long long v = r.integer(*n, "solver.max_order");
    if (v < 1 || v > 5) r.fail(*n, fmt::format("'solver.max_order' = {} must be an integer from 1 to 5", v));
    sol.max_order = static_cast<int>(v);
  }
  if (const toml::node* n = s->get("initial_step")) {
    const double v = r.number(*n, "solver.initial_step");
    if (!(v >= 0.0))
      r.fail(*n, fmt::format("'solver.initial_step' = {} must be >= 0 (0: estimated at the start)", v));
    sol.initial_step = v;
  }
  if (const toml::node* n = s->get("jacobian")) {
    static constexpr std::array<std::string_view, 3> kJacobians{"exact", "central", "ida_dq"};
    sol.jacobian = std::string(kJacobians[r.choice(*n, "solver.jacobian", kJacobians)]);
  }
  if (const toml::node* n = s->get("linear_solver")) {
    static constexpr std::array<std::string_view, 2> kLinearSolvers{"dense", "klu"};
    sol.linear_solver = std::string(kLinearSolvers[r.choice(*n, "solver.linear_solver", kLinearSolvers)]);
    if (sol.linear_solver == "klu" && sol.jacobian == "ida_dq")
      r.fail(*n, "'solver.linear_solver' = \"klu\" needs 'solver.jacobian' = \"exact\" or \"central\" (IDA's "
                 "difference quotients fill dense matrices only)");
  }
  // The integrator and, for it, the scheme (the formulation is read first).
  if (const toml::node* n = s->get("integrator")) {
    const std::vector<std::string> names = integrator_names();
    const std::vector<std::string_view> views(names.begin(), names.end());
    sol.integrator = names[r.choice(*n, "solver.integrator", views)];
    // An ODE integrator without a scheme in the file runs the ODE form with projection.
    const toml::table* f = root.get_as<toml::table>("formulation");
    if (find_integrator(sol.integrator).is_ode && !(f && f->contains("scheme")))
      scene.formulation.scheme = "projection";
    try {
      check_integrator_scheme(sol.integrator, scene.formulation.scheme);
    } catch (const InputError& e) {
      r.fail(*n, fmt::format("'solver.integrator' = \"{}\": {}", sol.integrator, e.what()));
    }
  }
  if (const toml::node* n = s->get("erk_method")) {
    const std::vector<std::string> names = erk_method_names();
    const std::vector<std::string_view> views(names.begin(), names.end());
    sol.erk_method = names[r.choice(*n, "solver.erk_method", views)];
  }
}

// After everything else: whether an exact solution exists depends on the
// whole scene.
void read_reference_kind(const TomlReader& r, const toml::table& root, Scene& scene) {
  const toml::node* n = root.get("reference");
  if (!n) return;
  static constexpr std::array<std::string_view, 3> kKinds{"auto", "exact", "tight"};
  scene.reference = static_cast<ReferenceKind>(r.choice(*n, "reference", kKinds));
  if (scene.reference != ReferenceKind::Exact) return;
  std::string why;
  if (exact::find_exact_solution(scene, &why)) return;
  r.fail(*n, fmt::format("'reference' = \"exact\" but this scene has no closed-form solution: {} (use \"auto\" "
                         "or \"tight\" for a tight run of quaternion/euler/ggl)",
                         why));
}

Scene read_scene(const TomlReader& r, const toml::table& root) {
  Scene scene;
  scene.source = r.file();
  if (root.empty())
    r.fail(root.source(), "the scene is empty (nothing but whitespace or comments); a scene needs "
                          "schema_version = 1 and the tables [body], [initial] and [time] (see "
                          "docs/scene_format.md and problems/*.toml)");

  // The version first: a file of another version should fail on that, not on
  // the keys it renamed.
  // (Unless it is missing: then a misspelt key is the likelier cause.)
  if (!root.get("schema_version")) r.check_keys(root, "", kRootKeys, kAllSections);
  const toml::node& ver = r.required(root, "", "schema_version", "schema_version = 1");
  const long long version = r.integer(ver, "schema_version");
  if (version != kSchemaVersion)
    r.fail(ver, fmt::format("unsupported schema_version {}; this version of rigidae reads "
                            "schema_version = {}",
                            version, kSchemaVersion));
  r.check_keys(root, "", kRootKeys, kAllSections);

  scene.name = std::filesystem::path(r.file()).stem().string();
  if (const toml::node* n = root.get("name")) {
    scene.name = r.string(*n, "name");
    if (scene.name.empty()) r.fail(*n, "'name' must not be empty (leave it out to use the file name)");
    // The name names the default output folder out/NAME-...: no paths, no hidden folders.
    const bool control = std::any_of(scene.name.begin(), scene.name.end(),
                                     [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
    if (scene.name.size() > kMaxNameBytes || control || scene.name.front() == '.' ||
        scene.name.find_first_of("/\\") != std::string::npos)
      r.fail(*n, fmt::format("'name' = \"{}\" cannot name an output folder: give at most {} bytes of printable "
                             "characters, without '/' or '\\' and not starting with '.' (e.g. \"heavy_top\")",
                             printable(scene.name), kMaxNameBytes));
  }
  if (const toml::node* n = root.get("description")) scene.description = r.string(*n, "description");

  const InertiaSource inertia = read_body(r, root, scene);
  read_support(r, root, scene);
  check_triangle_inequality(r, inertia, scene);
  read_gravity(r, root, scene);
  read_initial(r, root, scene);
  read_time(r, root, scene);
  read_formulation(r, root, scene);
  read_solver(r, root, scene);
  read_reference_kind(r, root, scene);
  return scene;
}

// The code point at a parser position (line and column counted in code
// points, from 1), or -1 past the end of the text or at an invalid sequence.
long code_point_at(std::string_view text, const toml::source_position& pos) {
  std::size_t i = 0;
  for (toml::source_index line = 1; line < pos.line; ++line) {
    i = text.find('\n', i);
    if (i == std::string_view::npos) return -1;
    ++i;
  }
  for (toml::source_index col = 1; i < text.size(); ++col) {
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t len = c < 0x80 ? 1 : c >= 0xf0 ? 4 : c >= 0xe0 ? 3 : c >= 0xc0 ? 2 : 0;
    if (len == 0 || i + len > text.size()) return -1;
    if (col == pos.column) {
      long cp = len == 1 ? c : c & (0xff >> (len + 1));
      for (std::size_t k = 1; k < len; ++k) cp = (cp << 6) | (static_cast<unsigned char>(text[i + k]) & 0x3f);
      return cp;
    }
    if (c == '\n') return -1;
    i += len;
  }
  return -1;
}

// toml++'s description of a syntax error, with what it usually means added
// where its words alone mislead.
std::string explain_parse_error(std::string_view text, const toml::parse_error& e) {
  // The parser's words may quote the input raw (a newline, an escape byte): escaped, one line.
  std::string msg = fmt::format("invalid TOML: {}", printable(e.description(), 1000));
  const long cp = code_point_at(text, e.source().begin);
  if (e.description().find("utf-8") != std::string_view::npos)
    msg += " (the file is not UTF-8 text: a binary file, or text saved in another encoding such as Latin-1)";
  else if (e.description().find("control characters") != std::string_view::npos && (cp == '\n' || cp == '\r' || cp < 0))
    msg += " (the string is not closed before the end of the line; a \"...\" string ends on its own line, "
           "use \"\"\"...\"\"\" for several lines)";
  else if (cp >= 0x80)
    msg += fmt::format(" (the character there is U+{:04X}, not ASCII: keys without quotes, numbers, '=' and "
                       "the spaces between them must be ASCII; look for a look-alike letter, digit or space)",
                       cp);
  return msg;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& source_name) {
  const TomlReader reader(source_name);
  toml::table root;
  try {
    root = toml::parse(std::string_view(text), std::string_view(source_name));
  } catch (const toml::parse_error& e) {
    reader.fail(e.source(), explain_parse_error(text, e));
  }
  return read_scene(reader, root);
}

Scene load_scene(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(fmt::format("{}: error: cannot read scene file '{}': it is a directory", path, path));
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw InputError(fmt::format("{}: error: cannot open scene file '{}': {}", path, path,
                                 err ? std::strerror(err) : "unreadable"));
  }
  // Read at most one byte more than a scene may have: a huge file or a
  // device such as /dev/zero is refused without reading it all.
  std::string text(kMaxSceneBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw InputError(fmt::format("{}: error: cannot read scene file '{}'", path, path));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxSceneBytes)
    throw InputError(fmt::format("{}: error: scene file '{}' is larger than {} bytes; a scene is a short TOML "
                                 "file (see problems/*.toml)",
                                 path, path, kMaxSceneBytes));
  return parse_scene(text, path);
}

}  // namespace rigidae::io
