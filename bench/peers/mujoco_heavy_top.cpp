// Peer: MuJoCo 2.2.2 (Debian libmujoco-dev), fixed time step. The top is a
// body at the world origin with a ball joint at its origin (the pivot); its
// <inertial> puts the COM at (0, 1, 0) with the COM inertia as diaginertia.
// The ball joint's qpos is the body-to-world quaternion (w, x, y, z) and its
// qvel the angular velocity in body components, so w0 goes in as given.
// Gravity (0, 0, -9.81), no damping, no armature, contacts disabled (the
// body has no geom anyway).
//
// Integrators of this MuJoCo version: Euler (semi-implicit), RK4, implicit
// ("implicitfast" came in a later release). One JSON line per
// (integrator, dt). The run takes N = round(2 / dt) steps of exactly 2 / N
// (reported as dt_used), so it ends at t = 2 whatever dt was asked for (a
// 1e-6 s overshoot alone is 1.5e-4 rad at 150 rad/s). rhs_evals is derived, not counted:
// forward-dynamics evaluations per step are 4 for RK4 (mj_forward plus three
// mj_forwardSkip stages) and 1 for Euler and implicit. Wall time covers
// mj_resetData, setting the initial state and all the steps (median of
// --repeats); compiling the model is outside it.
#include <mujoco/mujoco.h>

#include <cstring>
#include <memory>

#include "peer_common.hpp"

namespace {

std::string mjcf(const char* integrator, double dt) {
  char buf[2048];
  std::snprintf(buf, sizeof buf, R"(<mujoco model="%s">
  <compiler angle="radian"/>
  <option timestep="%.17g" integrator="%s" gravity="%.17g %.17g %.17g">
    <flag contact="disable"/>
  </option>
  <worldbody>
    <body name="top" pos="0 0 0">
      <joint name="pivot" type="ball" pos="0 0 0" damping="0" armature="0"/>
      <inertial pos="%.17g %.17g %.17g" mass="%.17g" diaginertia="%.17g %.17g %.17g"/>
    </body>
  </worldbody>
</mujoco>
)",
                peers::scene.name.c_str(), dt, integrator, peers::scene.gravity[0], peers::scene.gravity[1], peers::scene.gravity[2], peers::scene.com[0],
                peers::scene.com[1], peers::scene.com[2], peers::scene.mass, peers::scene.Icom[0], peers::scene.Icom[1], peers::scene.Icom[2]);
  return buf;
}

mjModel* compile(const std::string& xml) {
  auto vfs = std::make_unique<mjVFS>();  // large struct: keep it off the stack
  mj_defaultVFS(vfs.get());
  const char* name = "heavy_top.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0)
    throw std::runtime_error("mj_makeEmptyFileVFS failed");
  const int i = mj_findFileVFS(vfs.get(), name);
  std::memcpy(vfs->filedata[i], xml.data(), xml.size());
  char err[1000] = "";
  mjModel* m = mj_loadXML(name, vfs.get(), err, sizeof err);
  mj_deleteVFS(vfs.get());
  if (!m) throw std::runtime_error(std::string("mj_loadXML: ") + err);
  return m;
}

// MuJoCo prints warnings on stdout by default; keep stdout for JSON lines.
void warn_to_stderr(const char* msg) { std::fprintf(stderr, "mujoco_heavy_top: MuJoCo warning: %s\n", msg); }

void set_initial(const mjModel* m, mjData* d) {
  mj_resetData(m, d);
  d->qpos[0] = 1.0;
  d->qpos[1] = d->qpos[2] = d->qpos[3] = 0.0;
  for (int k = 0; k < 3; ++k) d->qvel[k] = peers::scene.w0[k];
}

// Kinetic 1/2 v^T M v from MuJoCo's mass matrix plus potential -m g . x_com
// from its COM position (computed here: mj_energyPos/Vel need the energy flag).
double total_energy(const mjModel* m, mjData* d) {
  mj_forward(m, d);
  mjtNum Mv[3];
  mj_mulM(m, d, Mv, d->qvel);
  const double kinetic = 0.5 * (d->qvel[0] * Mv[0] + d->qvel[1] * Mv[1] + d->qvel[2] * Mv[2]);
  const mjtNum* x = d->xipos + 3;  // body 1 (the top)
  const double potential = -m->body_mass[1] * (m->opt.gravity[0] * x[0] + m->opt.gravity[1] * x[1] +
                                               m->opt.gravity[2] * x[2]);
  return kinetic + potential;
}

}  // namespace

int main(int argc, char** argv) try {
  const char* usage =
      "mujoco_heavy_top [--scene heavy_top|free_body] [--repeats N] [--budget S] [--settings dt,dt,...] [--methods RK4,Euler,implicit]\n"
      "  [--reference FILE]  (default dt 1e-3, 5e-4, 2e-4, 1e-4, ..., 3e-6, 2e-6, 1e-6;\n"
      "  free_body: 1e-2 ... 5e-5)";
  auto opt = peers::parse_options(argc, argv, usage);
  if (opt.settings.empty()) {
    if (peers::scene.name == "free_body")  // 20 s: at most 400,000 steps
      opt.settings = {1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5};
    else
      opt.settings = {1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 3e-6, 2e-6, 1e-6};
  }
  const auto q_ref = peers::load_reference(opt.reference);
  mju_user_warning = warn_to_stderr;
  std::fprintf(stderr, "mujoco_heavy_top: MuJoCo %s\n", mj_versionString());

  const std::pair<const char*, int> methods[] = {{"RK4", 4}, {"Euler", 1}, {"implicit", 1}};
  for (const auto& [name, evals_per_step] : methods) {
    if (!peers::wanted(opt, name)) continue;
    for (double dt : opt.settings) {
      const long long steps = std::llround(peers::scene.t_end / dt);
      const double dt_used = peers::scene.t_end / static_cast<double>(steps);
      mjModel* m = compile(mjcf(name, dt_used));
      mjData* d = mj_makeData(m);
      // Verify the model against the scene before timing anything.
      set_initial(m, d);
      const double E0 = total_energy(m, d);
      const double E0_analytic = peers::initial_energy();
      if (m->nq != 4 || m->nv != 3 || std::fabs(E0 - E0_analytic) > 1e-9 * E0_analytic)
        throw std::runtime_error("model mismatch: nq " + std::to_string(m->nq) + ", E0 " +
                                 peers::num(E0) + " vs " + peers::num(E0_analytic));
      for (int k = 0; k < 3; ++k)  // mass matrix = inertia about the pivot
        if (std::fabs(d->qM[m->dof_Madr[k]] - peers::scene.Jpivot[k]) > 1e-12)
          throw std::runtime_error("mass matrix diagonal differs from J about the pivot");

      auto run = [&] {
        set_initial(m, d);
        for (long long s = 0; s < steps; ++s) mj_step(m, d);
      };
      const auto [wall, n] = peers::median_wall(run, opt.repeats, opt.budget_s);
      // On a bad acceleration (NaN/Inf) mj_step warns and resets the data to
      // the model's defaults, so a diverged run ends with d->time short of 2.
      const bool diverged = std::fabs(d->time - peers::scene.t_end) > 0.5 * dt_used;
      const double E = total_energy(m, d);

      peers::Row row;
      row.peer = "mujoco";
      row.method = name;
      row.setting_kind = "dt";
      row.setting = dt;
      row.wall_s = wall;
      row.repeats = n;
      row.steps = steps;
      row.rhs_evals = steps * evals_per_step;
      row.q_final = peers::normalized({d->qpos[0], d->qpos[1], d->qpos[2], d->qpos[3]});
      if (q_ref && !diverged) row.error_rad = peers::angle_between(*q_ref, row.q_final);
      row.extra = "\"dt_used\": " + peers::num(dt_used) + ", \"diverged\": " + (diverged ? "true" : "false") +
                  ", \"t_final\": " + peers::num(d->time) +
                  ", \"rel_energy_drift\": " + peers::num(std::fabs(E - E0) / E0) +
                  ", \"rhs_evals_derived\": true";
      peers::print_row(row);
      mj_deleteData(d);
      mj_deleteModel(m);
    }
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "mujoco_heavy_top: %s\n", e.what());
  return 1;
}
