// The geometry of a scene for the tools that draw a run (app/scene_geometry.hpp).
//
// One path for every scene: the bodies and joints of the system it runs as
// (as_system). Frames: a body held at a pivot is drawn in a frame whose
// origin is the pivot (fixed in space, the body's `pivot`: a one-body
// scene's body origin, the fixed point of a top, or a free body's centre of
// mass), any other body in a frame whose origin is its centre of mass (its
// trajectory.csv columns BODY.x..z place it); either turns by its columns
// qw..qz (prefixed by the body's column prefix). A shape's pose in its body
// frame is (position_B, R_BV); a point of the shape is
// x_W = x_body + R_WB (position_B + R_BV x_V).
// The default shape of a body is its inertia ellipsoid (the uniform solid
// ellipsoid with the body's mass and principal moments), centred at the
// centre of mass with its axes along the principal axes.
#include "rigidae/app/scene_geometry.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "rigidae/core/error.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/record/run_columns.hpp"

namespace rigidae {

namespace {

using nlohmann::json;

json vec(const Vec3& v) { return json::array({v[0], v[1], v[2]}); }

// Scalar-first unit quaternion of a rotation matrix.
json quat(const Mat3& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1.0;
  return json::array({q.w(), q.x(), q.y(), q.z()});
}

json shape_json(const VisualShape& v) {
  json s{{"shape", std::string(visual_kind_name(v.kind))},
         {"position", vec(v.position_B)},
         {"quaternion", quat(v.R_BV)}};
  if (v.kind == VisualKind::Box) s["size"] = vec(v.size);
  else s["radius"] = v.radius;
  if (v.kind == VisualKind::Cylinder || v.kind == VisualKind::Capsule) s["length"] = v.length;
  return s;
}

// Half the largest extent of a shape, measured from the body origin.
double shape_reach(const VisualShape& v) {
  const double r = v.kind == VisualKind::Box ? 0.5 * v.size.norm() : v.radius + 0.5 * v.length;
  return v.position_B.norm() + r;
}

json ellipsoid_json(double mass, const Mat3& inertia_com, const Vec3& center_B, double* reach) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(inertia_com);
  Mat3 axes = eig.eigenvectors();  // columns: principal axes in the body frame
  if (axes.determinant() < 0) axes.col(2) *= -1.0;
  const Vec3 semi = inertia_ellipsoid_semi_axes(mass, eig.eigenvalues());
  *reach = center_B.norm() + semi.maxCoeff();
  return json{{"shape", "ellipsoid"},
              {"semi_axes", vec(semi)},
              {"position", vec(center_B)},
              {"quaternion", quat(axes)}};
}

json body_json(const std::string& name, const std::string& columns, double mass, const Mat3& inertia_com,
               const Vec3& com_B, const std::vector<VisualShape>& visuals, double* reach) {
  json shapes = json::array();
  *reach = 0.0;
  for (const VisualShape& v : visuals) {
    shapes.push_back(shape_json(v));
    *reach = std::max(*reach, shape_reach(v));
  }
  const bool ellipsoid = visuals.empty();
  if (ellipsoid) shapes.push_back(ellipsoid_json(mass, inertia_com, com_B, reach));
  return json{{"name", name},          {"columns", columns},  {"mass", mass},
              {"center_of_mass", vec(com_B)}, {"visuals", shapes}, {"inertia_ellipsoid", ellipsoid}};
}


}  // namespace

Vec3 inertia_ellipsoid_semi_axes(double mass, const Vec3& J, double min_fraction) {
  Vec3 a;
  for (int i = 0; i < 3; ++i) {
    const double s = J[(i + 1) % 3] + J[(i + 2) % 3] - J[i];
    a[i] = std::sqrt(std::max(0.0, 5.0 * s / (2.0 * mass)));
  }
  const double floor = min_fraction * a.maxCoeff();
  for (int i = 0; i < 3; ++i) a[i] = std::max(a[i], floor);
  return a;
}

std::string scene_geometry_json(const Scene& scene) {
  // The system the scene runs as (a one-body scene: one body pivoted at the
  // fixed point, or at its centre of mass when free), body by body, with
  // the column prefix its records give each body (record/run_columns.hpp).
  const Scene system = as_system(scene);
  const MultibodySpec& mb = *system.multibody;
  json g{{"scene", scene.name}, {"source", scene.source}};
  if (scene.schema_version > 0) g["schema_version"] = scene.schema_version;
  // Each body's drawing frame: its body axes, origin at its pivot when it is
  // held at one (fixed in space: the body's `pivot`), else at its centre of
  // mass (placed by the columns x..z). `lever[i]` is that origin -> centre
  // of mass (body frame): what is added to a point given from the centre of
  // mass. A one-body scene's frame is then its body origin, as written.
  std::vector<Vec3> lever(mb.bodies.size(), Vec3::Zero());
  for (std::size_t i = 0; i < mb.bodies.size(); ++i)
    if (const BodySpec& b = mb.bodies[i]; b.pivot_W)
      lever[i] = b.com_from_pivot_B.value_or(Vec3(b.R0_WB.transpose() * (b.x0_W - *b.pivot_W)));
  const auto in_frame = [&](int body, const Vec3& p) -> Vec3 {
    return body == kGround ? p : Vec3(p + lever[static_cast<std::size_t>(body)]);
  };

  json bodies = json::array(), joints = json::array();
  double reach = 0.0, r = 0.0;
  for (std::size_t i = 0; i < mb.bodies.size(); ++i) {
    const BodySpec& b = mb.bodies[i];
    std::vector<VisualShape> visuals = b.visuals;
    for (VisualShape& v : visuals) v.position_B += lever[i];
    bodies.push_back(body_json(b.name, body_column_prefix(mb, i), b.mass, b.inertia_com, lever[i], visuals, &r));
    if (b.pivot_W) bodies.back()["pivot"] = vec(*b.pivot_W);
    reach = std::max(reach, r);
  }
  for (const JointSpec& j : mb.joints) {
    // The reaction in trajectory.csv acts on b at its point (on a when b is
    // the ground): the marker and the arrow go there.
    const bool on_b = j.body_b != kGround;
    const Vec3 pa = in_frame(j.body_a, j.point_a), pb = in_frame(j.body_b, j.point_b);
    joints.push_back(json{{"name", j.name},
                          {"type", std::string(j.type->name)},
                          {"body", on_b ? j.body_b : j.body_a},
                          {"point", vec(on_b ? pb : pa)},
                          {"other", on_b ? j.body_a : j.body_b},
                          {"other_point", vec(on_b ? pa : pb)},
                          {"reaction", j.name + "."}});
    reach = std::max({reach, pa.norm(), pb.norm()});
  }
  // A pivot holds its body like a spherical joint to the ground at the
  // frame's origin; its support force is the body's pivot_force columns.
  for (std::size_t i = 0; i < mb.bodies.size(); ++i)
    if (const BodySpec& b = mb.bodies[i]; b.pivot_W)
      joints.push_back(json{{"name", b.name + ".pivot"},
                            {"type", "spherical"},
                            {"body", static_cast<int>(i)},
                            {"point", vec(Vec3::Zero())},
                            {"other", kGround},
                            {"other_point", vec(*b.pivot_W)},
                            {"reaction", body_column_prefix(mb, i) + "pivot_"}});
  // The scene's size: the spread of the bodies' frame origins (the pivots,
  // the other bodies' centres of mass) and of the joints' ground points at
  // the start, plus twice the farthest a shape or joint point reaches from
  // its frame's origin (a body turns about it).
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (std::size_t i = 0; i < mb.bodies.size(); ++i) {
    const BodySpec& b = mb.bodies[i];
    const Vec3 origin = b.x0_W - b.R0_WB * lever[i];
    lo = lo.cwiseMin(origin), hi = hi.cwiseMax(origin);
  }
  // Joint points on the ground too (a particle's rod hangs from one).
  for (const JointSpec& j : mb.joints)
    for (const auto& [body, point] : {std::pair{j.body_a, j.point_a}, std::pair{j.body_b, j.point_b}})
      if (body == kGround) lo = lo.cwiseMin(point), hi = hi.cwiseMax(point);
  g["extent"] = (hi - lo).norm() + 2.0 * reach;
  // A particle has no orientation (no BODY.qw columns) and no inertia
  // ellipsoid: drawn as a small sphere (2 % of the scene's size) unless the
  // scene gives its visual.
  const double extent = g["extent"].get<double>() > 0.0 ? g["extent"].get<double>() : 1.0;
  for (std::size_t i = 0; i < mb.bodies.size(); ++i) {
    if (!mb.bodies[i].particle) continue;
    json& b = bodies[i];
    b["particle"] = true;
    if (!mb.bodies[i].visuals.empty()) continue;
    b["inertia_ellipsoid"] = false;
    b["visuals"] = json::array({json{{"shape", "sphere"},
                                     {"radius", 0.02 * extent},
                                     {"position", vec(Vec3::Zero())},
                                     {"quaternion", json::array({1.0, 0.0, 0.0, 0.0})}}});
  }
  // Markers ([[markers]]): a point fixed in a body, in its drawing frame as
  // the joints' points (drawn with their paths).
  json markers = json::array();
  for (const MarkerSpec& m : mb.markers)
    markers.push_back(json{{"name", m.name}, {"body", m.body}, {"point", vec(in_frame(m.body, m.point))}});
  g["bodies"] = bodies;
  g["joints"] = joints;
  g["markers"] = markers;
  return g.dump(1);
}

std::vector<std::filesystem::path> run_folders(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  if (fs::exists(dir / "summary.json")) return {dir};
  std::vector<fs::path> runs;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_directory() && fs::exists(e.path() / "summary.json")) runs.push_back(e.path());
  std::sort(runs.begin(), runs.end());
  if (runs.empty())
    throw InputError(fmt::format("'{}' is not a run folder: it holds no summary.json, nor do its sub-folders (give "
                                 "the folder of a solve, or of a compare)",
                                 dir.string()));
  return runs;
}

std::filesystem::path run_scene_file(const std::filesystem::path& run, const std::filesystem::path& override_path) {
  namespace fs = std::filesystem;
  if (!override_path.empty()) {
    if (!fs::exists(override_path)) throw InputError(fmt::format("--scene '{}' does not exist", override_path.string()));
    return override_path;
  }
  std::ifstream in(run / "summary.json");
  json s;
  try {
    s = json::parse(in);
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: cannot read it as JSON ({})", (run / "summary.json").string(), e.what()));
  }
  std::string scene;
  if (s.contains("configuration") && s["configuration"].contains("scene") && s["configuration"]["scene"].is_string())
    scene = s["configuration"]["scene"].get<std::string>();
  else if (s.contains("source") && s["source"].is_string())
    scene = s["source"].get<std::string>();
  if (scene.empty())
    throw InputError(fmt::format("{} names no scene file; give it with --scene FILE", (run / "summary.json").string()));
  if (!fs::exists(scene))
    throw InputError(fmt::format("the scene of {} is '{}' (relative to the folder it was solved in), which does not "
                                 "exist from here; give it with --scene FILE",
                                 run.string(), scene));
  return scene;
}

}  // namespace rigidae
