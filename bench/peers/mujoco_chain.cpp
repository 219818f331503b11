// Peer: MuJoCo 2.2.2 (Debian libmujoco-dev), fixed time step, on rigidae's
// multibody scenes (peer_multibody.hpp): the N-link spherical chain of
// tools/make_chain.py and the double pendulum of problems/double_pendulum.toml.
//
// Joint coordinates: nested <body> elements, each with a ball joint at its
// frame origin; a body's frame sits at its joint point (pos = the joint
// relative to the parent's joint, or to the world origin), axes = the scene's
// body axes, and <inertial pos="COM - joint" mass diaginertia="COM moments">.
// A ball joint's qpos is the quaternion of the body relative to its parent
// and its qvel the relative angular velocity in the body's axes; at t = 0
// every R is I, so qvel is the scene's angular velocity minus the parent's.
// Contacts disabled, no geoms, no damping or armature.
//
// Before anything is timed: the initial COM positions (xipos) must equal the
// scene's (1e-14) and the total energy (1/2 v^T M v from MuJoCo's mass matrix
// plus -sum m g . xipos) the analytic one and rigidae's (1e-12 relative).
//
// Integrators: RK4 and Euler (semi-implicit). A run takes N = round(t_end /
// dt) steps of exactly t_end / N (dt_used); rhs_evals is derived (4 per RK4
// step, 1 per Euler step). Wall time covers mj_resetData, the initial state
// and the N mj_step calls (median of --repeats), not the XML compile.
#include <mujoco/mujoco.h>

#include <cstring>
#include <memory>

#include "peer_multibody.hpp"

namespace {

std::string fmt3(const mb::Vec& v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g", v[0], v[1], v[2]);
  return buf;
}

// The model as MJCF files: the main one and, every kBodiesPerFile bodies, an
// <include>d one. The scene's bodies must form a chain in order (body b's
// parent is b - 1; true of both scenes), nested one inside the other; MuJoCo's
// XML parser (tinyxml2) refuses elements nested deeper than 100 in one file,
// but an included file is parsed on its own and its elements inserted where
// the <include> stands, so a 1000-link chain is 20 files of 50 bodies.
constexpr int kBodiesPerFile = 50;
using Files = std::vector<std::pair<std::string, std::string>>;  // (name, text); the first is the main file

Files mjcf(const mb::Scene& s, const char* integrator, double dt) {
  const int nb = static_cast<int>(s.bodies.size());
  for (int b = 0; b < nb; ++b)
    if (s.bodies[b].parent != b - 1) throw std::runtime_error("mujoco_chain: bodies must form a chain in order");
  Files files;
  std::string xml = "<mujoco model=\"" + s.name + "\">\n  <compiler angle=\"radian\"/>\n";
  char buf[512];
  std::snprintf(buf, sizeof buf, "  <option timestep=\"%.17g\" integrator=\"%s\" gravity=\"%s\">\n", dt, integrator,
                fmt3(s.gravity).c_str());
  xml += buf;
  xml += "    <flag contact=\"disable\"/>\n  </option>\n  <worldbody>\n";
  mb::Vec parent_joint{0.0, 0.0, 0.0};
  for (int first = 0; first < nb; first += kBodiesPerFile) {
    const int last = std::min(nb, first + kBodiesPerFile);
    if (first > 0) xml = "<mujoco>\n";
    for (int i = first; i < last; ++i) {
      const mb::Body& b = s.bodies[i];
      xml += "<body name=\"" + b.name + "\" pos=\"" + fmt3(mb::sub(b.joint, parent_joint)) + "\">";
      xml += "<joint type=\"ball\" pos=\"0 0 0\" damping=\"0\" armature=\"0\"/>";
      std::snprintf(buf, sizeof buf, "<inertial pos=\"%s\" mass=\"%.17g\" diaginertia=\"%s\"/>\n",
                    fmt3(mb::sub(b.com, b.joint)).c_str(), b.mass, fmt3(b.inertia).c_str());
      xml += buf;
      parent_joint = b.joint;
    }
    if (last < nb) xml += "<include file=\"part" + std::to_string(files.size() + 1) + ".xml\"/>\n";
    for (int i = first; i < last; ++i) xml += "</body>";
    xml += first == 0 ? "\n  </worldbody>\n</mujoco>\n" : "\n</mujoco>\n";
    files.emplace_back(first == 0 ? "chain.xml" : "part" + std::to_string(files.size()) + ".xml", xml);
  }
  return files;
}

mjModel* compile(const Files& files) {
  auto vfs = std::make_unique<mjVFS>();  // large struct: keep it off the stack
  mj_defaultVFS(vfs.get());
  for (const auto& [name, text] : files) {
    if (mj_makeEmptyFileVFS(vfs.get(), name.c_str(), static_cast<int>(text.size())) != 0)
      throw std::runtime_error("mj_makeEmptyFileVFS failed");
    const int i = mj_findFileVFS(vfs.get(), name.c_str());
    std::memcpy(vfs->filedata[i], text.data(), text.size());
  }
  char err[1000] = "";
  mjModel* m = mj_loadXML(files.front().first.c_str(), vfs.get(), err, sizeof err);
  mj_deleteVFS(vfs.get());
  if (!m) throw std::runtime_error(std::string("mj_loadXML: ") + err);
  return m;
}

void warn_to_stderr(const char* msg) { std::fprintf(stderr, "mujoco_chain: MuJoCo warning: %s\n", msg); }

void set_initial(const mb::Scene& s, const mjModel* m, mjData* d) {
  mj_resetData(m, d);
  for (int b = 0; b < static_cast<int>(s.bodies.size()); ++b) {
    const int qa = m->jnt_qposadr[b], va = m->jnt_dofadr[b];
    d->qpos[qa] = 1.0;
    d->qpos[qa + 1] = d->qpos[qa + 2] = d->qpos[qa + 3] = 0.0;
    const mb::Vec w = mb::relative_omega(s, b);
    for (int k = 0; k < 3; ++k) d->qvel[va + k] = w[k];
  }
}

double total_energy(const mjModel* m, mjData* d) {
  mj_forward(m, d);
  std::vector<mjtNum> Mv(m->nv);
  mj_mulM(m, d, Mv.data(), d->qvel);
  double e = 0.0;
  for (int i = 0; i < m->nv; ++i) e += 0.5 * d->qvel[i] * Mv[i];
  for (int b = 1; b < m->nbody; ++b) {
    const mjtNum* x = d->xipos + 3 * b;
    e -= m->body_mass[b] * (m->opt.gravity[0] * x[0] + m->opt.gravity[1] * x[1] + m->opt.gravity[2] * x[2]);
  }
  return e;
}

}  // namespace

int main(int argc, char** argv) try {
  const char* usage =
      "mujoco_chain [--scene chain|double_pendulum] [--links N] [--t-end T] [--repeats N] [--budget S]\n"
      "  [--settings dt,dt,...] [--methods RK4,Euler] [--reference FILE] [--check]\n"
      "  (default dt 1e-3, 3e-4, 1e-4, 3e-5, 1e-5)";
  auto opt = mb::parse_options(argc, argv, usage);
  const mb::Scene& scene = opt.scene;
  if (opt.settings.empty()) opt.settings = {1e-3, 3e-4, 1e-4, 3e-5, 1e-5};
  const auto ref = mb::load_reference(opt.reference, scene.bodies.size());
  if (!ref) std::fprintf(stderr, "mujoco_chain: no reference %s: errors are null\n", opt.reference.c_str());
  mju_user_warning = warn_to_stderr;
  const int nb = static_cast<int>(scene.bodies.size());

  {  // the model against the scene, once
    mjModel* m = compile(mjcf(scene, "RK4", 1e-3));
    mjData* d = mj_makeData(m);
    set_initial(scene, m, d);
    const double E0 = total_energy(m, d);
    if (m->nq != 4 * nb || m->nv != 3 * nb || m->nbody != nb + 1) throw std::runtime_error("model size mismatch");
    for (int b = 0; b < nb; ++b)
      if (mb::norm(mb::sub({d->xipos[3 * (b + 1)], d->xipos[3 * (b + 1) + 1], d->xipos[3 * (b + 1) + 2]},
                           scene.bodies[b].com)) > 1e-14)
        throw std::runtime_error("initial COM of " + scene.bodies[b].name + " differs from the scene's");
    std::fprintf(stderr, "mujoco_chain: MuJoCo %s\n", mj_versionString());
    mb::check_energy("mujoco_chain", scene, E0, ref);
    mj_deleteData(d);
    mj_deleteModel(m);
    if (opt.check_only) return 0;
  }

  const std::pair<const char*, int> methods[] = {{"RK4", 4}, {"Euler", 1}};
  for (const auto& [name, evals_per_step] : methods) {
    if (!mb::wanted(opt, name)) continue;
    for (double dt : opt.settings) {
      const long long steps = std::llround(scene.t_end / dt);
      const double dt_used = scene.t_end / static_cast<double>(steps);
      mjModel* m = compile(mjcf(scene, name, dt_used));
      mjData* d = mj_makeData(m);
      set_initial(scene, m, d);
      const double E0 = total_energy(m, d);
      auto run = [&] {
        set_initial(scene, m, d);
        for (long long s = 0; s < steps; ++s) mj_step(m, d);
      };
      const auto [wall, n] = peers::median_wall(run, opt.repeats, opt.budget_s);
      // On a bad acceleration mj_step warns and resets the data, so a diverged
      // run ends with d->time short of t_end.
      const bool diverged = std::fabs(d->time - scene.t_end) > 0.5 * dt_used;
      const double E = total_energy(m, d);  // mj_forward: xquat, xipos of the final state
      std::vector<peers::Quat> q;
      std::vector<mb::Vec> x;
      bool finite = true;
      for (int b = 1; b <= nb; ++b) {
        const mjtNum* qb = d->xquat + 4 * b;
        const mjtNum* xb = d->xipos + 3 * b;
        q.push_back(peers::normalized({qb[0], qb[1], qb[2], qb[3]}));
        x.push_back({xb[0], xb[1], xb[2]});
        for (int k = 0; k < 4; ++k) finite = finite && std::isfinite(qb[k]);
      }

      mb::Row row;
      row.peer = "mujoco";
      row.method = name;
      row.setting_kind = "dt";
      row.setting = dt;
      row.wall_s = wall;
      row.repeats = n;
      row.steps = steps;
      row.rhs_evals = steps * evals_per_step;
      if (ref && !diverged && finite) row.err = mb::errors(*ref, q, x);
      row.energy0 = E0;
      row.rel_energy_drift = std::fabs(E - E0) / std::max(std::fabs(E0), 1.0);
      row.extra = "\"dt_used\": " + peers::num(dt_used) + ", \"diverged\": " + (diverged || !finite ? "true" : "false") +
                  ", \"t_final\": " + peers::num(d->time) + ", \"rhs_evals_derived\": true";
      mb::print_row(scene, row);
      mj_deleteData(d);
      mj_deleteModel(m);
    }
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "mujoco_chain: %s\n", e.what());
  return 1;
}
