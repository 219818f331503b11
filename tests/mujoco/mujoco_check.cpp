// MuJoCo cross-check of the URDF import and the MJCF export (CTest
// mujoco_arm6, mujoco_double_pendulum, mujoco_chain_10, mujoco_joint_zoo,
// mujoco_heavy_top, mujoco_free_body; built only when Debian's libmujoco-dev
// is found). A one-body scene (schema 1) is checked as the system it runs as
// (as_system): its body on a ball joint at the fixed point (a free body: at
// its centre of mass).
//
//   mujoco_check RIGIDAE_CLI SCENE.toml URDF|- [DT]
//
// (writes into a fresh folder under $TMPDIR, which CTest sets)
// 1. `rigidae solve SCENE.toml --rtol 1e-11 --atol 1e-11 --t-end 1` writes
//    trajectory.csv: every body's quaternion and centre of mass on the
//    scene's output grid over 1 s (a body in the one-body columns, qw..qz
//    without a position: its centre of mass is pivot + R c, c the lever).
// 2. `rigidae export --mjcf SCENE.toml -o WORK_DIR/arm6.xml`.
// 3. Two MuJoCo 2.2.2 models, each RK4 with dt = 1e-4, contacts and joint
//    limits off, stepped 1 s:
//    (a) the exported MJCF, started from its keyframe 0;
//    (b) when a URDF is given: the URDF read by MuJoCo's OWN URDF parser
//        (independent of rigidae's reader: frames, rpy, inertial origins,
//        merging), started from the scene's [urdf] positions and velocities,
//        set by joint name.
// 4. rigidae's joint angles come from the bodies' orientations alone: for a
//    revolute joint from parent body a (or the ground) to child body b,
//    R_rel = R_a^T R_b, and between output times
//        R_rel(t_k) = R_rel(t_{k-1}) Rot(z_b, d_k),  d_k = z_b . log(R_rel(t_{k-1})^T R_rel(t_k)),
//    with z_b the joint axis in b's frame; theta(t_k) = theta(0) + sum d_k
//    (theta(0) the scene's position; summing steps unwraps turns past pi).
//    The part of the log off the axis must vanish (the joint holds).
// 5. Pass: |theta_rigidae - qpos_mujoco| <= 1e-6 rad for every revolute
//    joint at every output time (scenes of revolute joints only), and for
//    every body at every output time its orientation within 1e-6 rad (the
//    angle of R_mujoco^T R_rigidae) and its centre of mass within 1e-6 m
//    (MuJoCo bodies welded to a rigidae body counted in it); the initial
//    centres of mass within 1e-9 m.
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "rigidae/io/scene_loader.hpp"
#include "rigidae/model/one_body_system.hpp"
#include "rigidae/record/run_columns.hpp"
#include "rigidae/so3/rotation.hpp"

namespace {

using rigidae::Mat3;
using rigidae::Vec3;
using rigidae::Vec4;

constexpr double kAngleTolerance = 1e-6;  // rad: the criterion
constexpr double kStartTolerance = 1e-9;  // m: initial centres of mass
constexpr double kBodyTolerance = 1e-6;   // rad and m: bodies along the run
double kDt = 1e-4;  // s; the issue asks for <= 1e-4 (a 4th argument sets another, for convergence checks)

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  // The column `name` (a body's column prefix and what), or -1.
  int find(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    return -1;
  }
  int column(const std::string& name) const {
    const int i = find(name);
    if (i < 0) throw std::runtime_error("trajectory.csv has no column " + name);
    return i;
  }
};

Table read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  Table t;
  std::string line;
  while (std::getline(in, line) && !line.empty() && line[0] == '#') {}  // the units line
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) t.header.push_back(cell);
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::vector<double> row;
    for (std::string cell; std::getline(ls, cell, ',');) row.push_back(cell.empty() ? NAN : std::strtod(cell.c_str(), nullptr));
    t.rows.push_back(row);
  }
  return t;
}

void run(const std::string& command) {
  std::fprintf(stderr, "mujoco_check: %s\n", command.c_str());
  if (std::system(command.c_str()) != 0) throw std::runtime_error("command failed: " + command);
}

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};

std::unique_ptr<mjModel, MjModelDeleter> load(const std::string& path) {
  char err[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, err, sizeof err);
  if (!m) throw std::runtime_error("MuJoCo cannot load " + path + ": " + err);
  m->opt.integrator = mjINT_RK4;
  m->opt.timestep = kDt;
  m->opt.disableflags |= mjDSBL_CONTACT | mjDSBL_LIMIT;
  return std::unique_ptr<mjModel, MjModelDeleter>(m);
}

// Centre of mass of MuJoCo body `b` with the bodies welded to it (no joints
// of their own between them, and not rigidae bodies of their own: `own`
// marks those), in space, after mj_forward.
Vec3 welded_com(const mjModel* m, const mjData* d, int b, const std::vector<bool>& own) {
  double mass = 0.0;
  Vec3 c = Vec3::Zero();
  for (int k = 1; k < m->nbody; ++k) {
    if (k != b && own[k]) continue;
    int a = k;
    while (a != b && !own[a] && m->body_jntnum[a] == 0 && m->body_parentid[a] != 0) a = m->body_parentid[a];
    if (a != b) continue;
    mass += m->body_mass[k];
    c += m->body_mass[k] * Vec3(d->xipos[3 * k], d->xipos[3 * k + 1], d->xipos[3 * k + 2]);
  }
  return c / mass;
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc != 4 && argc != 5) {
    std::fprintf(stderr, "usage: mujoco_check RIGIDAE_CLI SCENE.toml URDF|- [DT]\n");
    return 2;
  }
  if (argc == 5) kDt = std::strtod(argv[4], nullptr);
  const std::string cli = argv[1], scene_path = argv[2], urdf_path = argv[3];
  std::string pattern = (std::filesystem::temp_directory_path() / "mujoco_check.XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot make a folder under " + pattern);
  const std::string work = pattern;
  const std::string run_dir = work + "/run", model_path = work + "/model.xml";
  std::filesystem::remove_all(run_dir);
  run("'" + cli + "' solve '" + scene_path + "' --out '" + run_dir + "' --record grid -q --rtol 1e-11 --atol 1e-11 --t-end 1");
  run("'" + cli + "' export --mjcf '" + scene_path + "' -o '" + model_path + "'");

  const rigidae::Scene scene = rigidae::as_system(rigidae::io::load_scene(scene_path));
  const rigidae::MultibodySpec& mb = *scene.multibody;
  std::vector<std::string> prefix;  // each body's columns in trajectory.csv
  for (std::size_t b = 0; b < mb.bodies.size(); ++b) prefix.push_back(rigidae::body_column_prefix(mb, b));
  const Table traj = read_csv(run_dir + "/trajectory.csv");
  const int nt = static_cast<int>(traj.rows.size());
  const auto R_at = [&](int body, int k) -> Mat3 {
    if (body < 0) return Mat3::Identity();
    const std::string& p = prefix[body];
    const auto& r = traj.rows[k];
    Vec4 q(r[traj.column(p + "qw")], r[traj.column(p + "qx")], r[traj.column(p + "qy")], r[traj.column(p + "qz")]);
    return rigidae::so3::quaternion_to_matrix(q / q.norm());
  };
  // A body's centre of mass: its columns x..z, or (none: the one-body
  // columns) from its pivot and orientation, pivot + R c.
  const auto x_at = [&](int body, int k) -> Vec3 {
    const std::string& p = prefix[body];
    const auto& r = traj.rows[k];
    if (traj.find(p + "x") >= 0) return Vec3(r[traj.column(p + "x")], r[traj.column(p + "y")], r[traj.column(p + "z")]);
    const rigidae::BodySpec& b = mb.bodies[body];
    if (!b.pivot_W) throw std::runtime_error("trajectory.csv has no column " + p + "x");
    const Vec3 c = b.com_from_pivot_B.value_or(Vec3(b.R0_WB.transpose() * (b.x0_W - *b.pivot_W)));
    return *b.pivot_W + R_at(body, k) * c;
  };

  // The scene's initial joint positions and rates, by URDF joint name.
  const toml::table tbl = toml::parse_file(scene_path);
  std::map<std::string, double> q0, qd0;
  if (const auto* t = tbl["urdf"]["positions"].as_table())
    for (auto&& [k, v] : *t) q0[std::string(k.str())] = v.value<double>().value();
  if (const auto* t = tbl["urdf"]["velocities"].as_table())
    for (auto&& [k, v] : *t) qd0[std::string(k.str())] = v.value<double>().value();

  // rigidae's joint angles from the orientations.
  const int nj = static_cast<int>(mb.joints.size());
  std::vector<std::vector<double>> theta(nj, std::vector<double>(nt));
  double worst_off_axis = 0.0;
  bool all_revolute = true;
  for (const rigidae::JointSpec& J : mb.joints) all_revolute = all_revolute && J.type->name == "revolute";
  for (int j = 0; j < nj && all_revolute; ++j) {
    const rigidae::JointSpec& J = mb.joints[j];
    theta[j][0] = q0.count(J.name) ? q0[J.name] : 0.0;
    for (int k = 1; k < nt; ++k) {
      const Mat3 prev = R_at(J.body_a, k - 1).transpose() * R_at(J.body_b, k - 1);
      const Mat3 now = R_at(J.body_a, k).transpose() * R_at(J.body_b, k);
      const Vec3 log = rigidae::so3::matrix_to_rotation_vector(prev.transpose() * now);
      const double d = J.axis_b.dot(log);
      worst_off_axis = std::max(worst_off_axis, (log - d * J.axis_b).norm());
      theta[j][k] = theta[j][k - 1] + d;
    }
  }
  std::printf("rigidae: %d bodies, %d joints, %d output times; largest turn off a joint axis between outputs %.2e rad\n",
              static_cast<int>(mb.bodies.size()), nj, nt, worst_off_axis);
  if (all_revolute) std::printf("rigidae: joint excursions over the run (max |theta(t) - theta(0)|, rad):");
  for (int j = 0; j < nj && all_revolute; ++j) {
    double most = 0.0;
    for (int k = 0; k < nt; ++k) most = std::max(most, std::abs(theta[j][k] - theta[j][0]));
    std::printf(" %s %.3f", mb.joints[j].name.c_str(), most);
  }
  if (all_revolute) std::printf("\n");

  bool ok = worst_off_axis < kAngleTolerance;
  const auto compare = [&](const char* label, const mjModel* m, mjData* d) {
    std::vector<int> qadr(nj);
    for (int j = 0; j < nj && all_revolute; ++j) {
      const int id = mj_name2id(m, mjOBJ_JOINT, mb.joints[j].name.c_str());
      if (id < 0) throw std::runtime_error(std::string(label) + ": no joint " + mb.joints[j].name);
      qadr[j] = m->jnt_qposadr[id];
    }
    std::vector<bool> own(m->nbody, false);
    for (const rigidae::BodySpec& b : mb.bodies)
      if (const int id = mj_name2id(m, mjOBJ_BODY, b.name.c_str()); id >= 0) own[id] = true;
    mj_forward(m, d);
    double start_err = 0.0;
    for (const rigidae::BodySpec& b : mb.bodies) {
      const int id = mj_name2id(m, mjOBJ_BODY, b.name.c_str());
      if (id < 0) throw std::runtime_error(std::string(label) + ": no body " + b.name);
      start_err = std::max(start_err, (welded_com(m, d, id, own) - b.x0_W).norm());
    }
    double worst = 0.0, worst_t = 0.0, body_rot = 0.0, body_com = 0.0;
    std::string worst_joint;
    const int steps_per_output = static_cast<int>(std::lround(scene.time.output_step / kDt));
    for (int k = 0; k < nt; ++k) {
      if (k > 0)
        for (int s = 0; s < steps_per_output; ++s) mj_step(m, d);
      double row_worst = 0.0;
      for (int j = 0; j < nj && all_revolute; ++j) {
        const double e = std::abs(d->qpos[qadr[j]] - theta[j][k]);
        row_worst = std::max(row_worst, e);
        if (!(e <= worst)) worst = e, worst_t = d->time, worst_joint = mb.joints[j].name;
      }
      for (int b = 0; b < static_cast<int>(mb.bodies.size()); ++b) {
        const std::string& n = mb.bodies[b].name;
        const int id = mj_name2id(m, mjOBJ_BODY, n.c_str());
        Mat3 R_mj;
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) R_mj(r, c) = d->xmat[9 * id + 3 * r + c];
        const Vec3 x = x_at(b, k);
        body_rot = std::max(body_rot, rigidae::so3::rotation_distance(R_mj, R_at(b, k)));
        body_com = std::max(body_com, (welded_com(m, d, id, own) - x).norm());
      }
      if (all_revolute && std::getenv("MUJOCO_CHECK_VERBOSE") && k % 10 == 0) std::printf("  t = %.2f s: worst joint error %.3e rad\n", d->time, row_worst);
    }
    std::printf("%-34s nq %d: initial COM within %.2e m; bodies within %.2e rad and %.2e m", label, m->nq, start_err,
                body_rot, body_com);
    if (all_revolute) std::printf("; joint angles within %.2e rad (worst: %s at t = %.2f s)", worst, worst_joint.c_str(), worst_t);
    std::printf("\n");
    ok = ok && start_err <= kStartTolerance && worst <= kAngleTolerance && body_rot <= kBodyTolerance &&
         body_com <= kBodyTolerance && std::abs(d->time - traj.rows.back()[0]) < 1e-9;
  };

  {
    auto m = load(model_path);
    std::unique_ptr<mjData, MjDataDeleter> d(mj_makeData(m.get()));
    if (m->nkey < 1) throw std::runtime_error("the exported model has no keyframe");
    mj_resetDataKeyframe(m.get(), d.get(), 0);
    compare("MuJoCo, rigidae's MJCF export:", m.get(), d.get());
  }
  if (urdf_path != "-") {
    auto m = load(urdf_path);
    std::unique_ptr<mjData, MjDataDeleter> d(mj_makeData(m.get()));
    mj_resetData(m.get(), d.get());
    for (const auto& [name, v] : q0) d->qpos[m->jnt_qposadr[mj_name2id(m.get(), mjOBJ_JOINT, name.c_str())]] = v;
    for (const auto& [name, v] : qd0) d->qvel[m->jnt_dofadr[mj_name2id(m.get(), mjOBJ_JOINT, name.c_str())]] = v;
    compare("MuJoCo, its own URDF parser:", m.get(), d.get());
  }
  std::printf("%s (tolerance %.0e rad, MuJoCo %s, RK4, dt %.0e s)\n", ok ? "PASS" : "FAIL", kAngleTolerance,
              mj_versionString(), kDt);
  return ok ? 0 : 1;
} catch (const std::exception& e) {
  std::fprintf(stderr, "mujoco_check: %s\n", e.what());
  return 1;
}
