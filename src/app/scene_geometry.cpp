// The geometry of a scene for the tools that draw a run (app/scene_geometry.hpp).
//
// Frames: a schema-2 body's frame has its origin at the centre of mass (its
// trajectory.csv columns BODY.x..z, BODY.qw..qz place it); a schema-1 body's
// at the body origin, the fixed point of a top (columns qw..qz; the origin
// stays at 0). A shape's pose in its body frame is (position_B, R_BV); a
// point of the shape is x_W = x_body + R_WB (position_B + R_BV x_V).
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
  json g{{"scene", scene.name}, {"source", scene.source}};
  json bodies = json::array(), joints = json::array();
  double reach = 0.0, r = 0.0;
  if (scene.multibody) {
    g["schema_version"] = 2;
    const MultibodySpec& mb = *scene.multibody;
    for (const BodySpec& b : mb.bodies) {
      bodies.push_back(body_json(b.name, b.name + ".", b.mass, b.inertia_com, Vec3::Zero(), b.visuals, &r));
      reach = std::max(reach, r);
    }
    for (const JointSpec& j : mb.joints) {
      // The reaction in trajectory.csv acts on b at its point (on a when b is
      // the ground): the marker and the arrow go there.
      const bool on_b = j.body_b != kGround;
      json joint{{"name", j.name},
                 {"type", std::string(j.type->name)},
                 {"body", on_b ? j.body_b : j.body_a},
                 {"point", vec(on_b ? j.point_b : j.point_a)},
                 {"other", on_b ? j.body_a : j.body_b},
                 {"other_point", vec(on_b ? j.point_a : j.point_b)},
                 {"reaction", j.name + "."}};
      joints.push_back(joint);
      reach = std::max({reach, j.point_a.norm(), j.point_b.norm()});
    }
    // The scene's size: its bodies' starting spread and their shapes.
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (const BodySpec& b : mb.bodies) lo = lo.cwiseMin(b.x0_W), hi = hi.cwiseMax(b.x0_W);
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
  } else {
    g["schema_version"] = 1;
    g["support"] = scene.support == Support::FixedPoint ? "fixed_point" : "free";
    const RigidBodySpec& b = scene.body;
    bodies.push_back(body_json("body", "", b.mass, b.inertia_com, b.com_B, b.visuals, &r));
    if (scene.support == Support::FixedPoint)
      joints.push_back(json{{"name", "fixed_point"},
                            {"type", "spherical"},
                            {"body", 0},
                            {"point", vec(Vec3::Zero())},
                            {"other", kGround},
                            {"other_point", vec(Vec3::Zero())},
                            {"reaction", nullptr}});
    g["extent"] = 2.0 * std::max(r, b.com_B.norm());
  }
  // Markers ([[markers]]): a point in a body's frame from its centre of
  // mass, as the joints' points (drawn with their paths).
  json markers = json::array();
  if (scene.multibody)
    for (const MarkerSpec& m : scene.multibody->markers)
      markers.push_back(json{{"name", m.name}, {"body", m.body}, {"point", vec(m.point)}});
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
