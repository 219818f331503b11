// Peer: Simbody 3.7 (Debian libsimbody-dev) on rigidae's multibody scenes
// (peer_multibody.hpp): the N-link spherical chain of tools/make_chain.py and
// the double pendulum of problems/double_pendulum.toml.
//
// Joint coordinates: each body is a MobilizedBody::Ball (quaternion q,
// generalized speeds u = angular velocity of the body relative to its parent,
// in the parent's axes) on its parent; the mobilizer's inboard frame F sits at
// the joint point in the parent (at the origin of Ground), its outboard frame
// M at the joint point in the body. Body frames sit at the centres of mass,
// aligned with the scene's body axes, so MassProperties take the COM inertia
// and the body origin is the COM. At t = 0 every R is I, so u is the scene's
// angular velocity minus the parent's. Force::Gravity (0, 0, -9.81).
//
// Before anything is timed: the initial COM positions and velocities Simbody
// computes from (q, u) must equal the scene's (1e-14), and its total energy
// must equal the analytic one and rigidae's (1e-12 relative, printed).
//
// One JSON line per (integrator, accuracy). Wall time covers integrator
// construction, initialize() and stepping 0 -> t_end (median of --repeats).
// steps = getNumStepsTaken(), rhs_evals = getNumRealizations().
#include <Simbody.h>

#include <functional>
#include <memory>

#include "peer_multibody.hpp"

using namespace SimTK;

namespace {

Vec3 v3(const mb::Vec& a) { return Vec3(a[0], a[1], a[2]); }

struct Model {
  MultibodySystem system;
  SimbodyMatterSubsystem matter{system};
  GeneralForceSubsystem forces{system};
  std::vector<MobilizedBody::Ball> bodies;
  State initial;

  explicit Model(const mb::Scene& s) {
    Force::Gravity(forces, matter, v3(s.gravity));
    bodies.reserve(s.bodies.size());
    for (int b = 0; b < static_cast<int>(s.bodies.size()); ++b) {
      const mb::Body& sb = s.bodies[b];
      Body::Rigid body(MassProperties(sb.mass, Vec3(0), Inertia(sb.inertia[0], sb.inertia[1], sb.inertia[2])));
      MobilizedBody& parent = sb.parent < 0 ? static_cast<MobilizedBody&>(matter.Ground()) : bodies[sb.parent];
      bodies.emplace_back(parent, Transform(v3(mb::joint_in_parent(s, b))), body, Transform(v3(mb::joint_in_child(s, b))));
    }
    system.realizeTopology();
    initial = system.getDefaultState();
    for (int b = 0; b < static_cast<int>(s.bodies.size()); ++b) {
      bodies[b].setQ(initial, Vec4(1, 0, 0, 0));
      bodies[b].setU(initial, v3(mb::relative_omega(s, b)));
    }
    system.realize(initial, Stage::Velocity);
  }

  void final_pose(const State& st, std::vector<peers::Quat>& q, std::vector<mb::Vec>& x) const {
    q.clear();
    x.clear();
    for (const auto& body : bodies) {
      const Quaternion qq = body.getBodyRotation(st).convertRotationToQuaternion();
      q.push_back(peers::normalized({qq[0], qq[1], qq[2], qq[3]}));
      const Vec3 p = body.getBodyOriginLocation(st);
      x.push_back({p[0], p[1], p[2]});
    }
  }
};

using Factory = std::function<std::unique_ptr<Integrator>(const System&)>;

}  // namespace

int main(int argc, char** argv) try {
  const char* usage =
      "simbody_chain [--scene chain|double_pendulum] [--links N] [--t-end T] [--repeats N] [--budget S]\n"
      "  [--settings acc,acc,...] [--methods m,m] [--reference FILE] [--check]\n"
      "  methods: RungeKuttaMerson, RungeKuttaFeldberg, CPodesBDF, RungeKutta3 (default: the first three;\n"
      "  accuracy 1e-3..1e-10)";
  auto opt = mb::parse_options(argc, argv, usage);
  const mb::Scene& scene = opt.scene;
  if (opt.settings.empty())
    for (int e = 3; e <= 10; ++e) opt.settings.push_back(std::pow(10.0, -e));
  if (opt.methods.empty()) opt.methods = {"RungeKuttaMerson", "RungeKuttaFeldberg", "CPodesBDF"};
  const auto ref = mb::load_reference(opt.reference, scene.bodies.size());
  if (!ref) std::fprintf(stderr, "simbody_chain: no reference %s: errors are null\n", opt.reference.c_str());

  Model model(scene);
  // The model against the scene: COM positions and velocities, then energy.
  for (int b = 0; b < static_cast<int>(scene.bodies.size()); ++b) {
    const auto& body = model.bodies[b];
    const double dx = (body.getBodyOriginLocation(model.initial) - v3(scene.bodies[b].com)).norm();
    const double dv = (body.getBodyOriginVelocity(model.initial) - v3(scene.bodies[b].velocity)).norm();
    const double dw = (body.getBodyAngularVelocity(model.initial) - v3(scene.bodies[b].omega)).norm();
    if (dx > 1e-14 || dv > 1e-14 || dw > 1e-14)
      throw std::runtime_error("initial state of " + scene.bodies[b].name + " differs from the scene's");
  }
  const double E0 = model.system.calcEnergy(model.initial);
  mb::check_energy("simbody_chain", scene, E0, ref);
  if (opt.check_only) return 0;

  const std::vector<std::pair<std::string, Factory>> methods = {
      {"RungeKuttaMerson", [](const System& s) { return std::make_unique<RungeKuttaMersonIntegrator>(s); }},
      {"RungeKuttaFeldberg", [](const System& s) { return std::make_unique<RungeKuttaFeldbergIntegrator>(s); }},
      {"CPodesBDF", [](const System& s) { return std::make_unique<CPodesIntegrator>(s, CPodes::BDF, CPodes::Newton); }},
      {"RungeKutta3", [](const System& s) { return std::make_unique<RungeKutta3Integrator>(s); }},
  };
  for (const auto& [name, make] : methods) {
    if (!mb::wanted(opt, name)) continue;
    for (double acc : opt.settings) {
      long long steps = 0, attempted = 0, realizations = 0, projections = 0;
      State final_state;
      auto run = [&] {
        auto integ = make(model.system);
        integ->setAccuracy(acc);
        integ->setFinalTime(scene.t_end);  // land on t_end exactly, no interpolated output
        integ->setInternalStepLimit(100000000);
        integ->initialize(model.initial);
        while (integ->getTime() < scene.t_end) {
          integ->stepTo(scene.t_end);
          if (integ->isSimulationOver()) break;
        }
        steps = integ->getNumStepsTaken();
        attempted = integ->getNumStepsAttempted();
        realizations = integ->getNumRealizations();
        projections = integ->getNumProjections();
        final_state = integ->getState();
      };
      const auto [wall, n] = peers::median_wall(run, opt.repeats, opt.budget_s);
      const bool reached = std::fabs(final_state.getTime() - scene.t_end) <= 1e-12;
      if (!reached)
        std::fprintf(stderr, "simbody_chain: %s acc %g stopped at t = %.17g\n", name.c_str(), acc,
                     final_state.getTime());
      model.system.realize(final_state, Stage::Velocity);
      std::vector<peers::Quat> q;
      std::vector<mb::Vec> x;
      model.final_pose(final_state, q, x);
      const double E = model.system.calcEnergy(final_state);

      mb::Row row;
      row.peer = "simbody";
      row.method = name;
      row.setting_kind = "accuracy";
      row.setting = acc;
      row.wall_s = wall;
      row.repeats = n;
      row.steps = steps;
      row.rhs_evals = realizations;
      if (ref && reached) row.err = mb::errors(*ref, q, x);
      row.energy0 = E0;
      row.rel_energy_drift = std::fabs(E - E0) / std::max(std::fabs(E0), 1.0);
      row.extra = "\"steps_attempted\": " + std::to_string(attempted) + ", \"projections\": " +
                  std::to_string(projections) + ", \"t_final\": " + peers::num(final_state.getTime());
      mb::print_row(scene, row);
    }
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "simbody_chain: %s\n", e.what());
  return 1;
}
