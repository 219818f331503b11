// Peer: Simbody 3.7 (Debian libsimbody-dev). The top is one body on a Ball
// mobilizer (quaternion coordinates) to Ground; the mobilizer frames coincide
// with Ground's and the body's frames, so the pivot is the body origin and
// the Ball's q is R_GB. Simbody's MassProperties take the inertia about the
// body origin, so the body gets J = I_com + m (|c|^2 1 - c c^T) =
// diag(15.234375, 0.46875, 15.234375) with the COM at (0, 1, 0).
//
// The Ball's generalized speeds are w_GB in Ground components; the initial
// orientation is the identity, so the body-frame w0 is also the space-frame one.
//
// One JSON line per (integrator, accuracy). Wall time covers integrator
// construction, initialize() and stepping 0 -> 2 s (median of --repeats).
// steps = getNumStepsTaken(), rhs_evals = getNumRealizations().
#include <Simbody.h>

#include <functional>
#include <map>
#include <memory>

#include "peer_common.hpp"

using namespace SimTK;

namespace {

struct Model {
  MultibodySystem system;
  SimbodyMatterSubsystem matter{system};
  GeneralForceSubsystem forces{system};
  MobilizedBody::Ball top;
  State initial;

  Model() {
    Force::Gravity(forces, matter, Vec3(peers::scene.gravity[0], peers::scene.gravity[1], peers::scene.gravity[2]));
    const Vec3 c(peers::scene.com[0], peers::scene.com[1], peers::scene.com[2]);
    const Inertia I_pivot(peers::scene.Jpivot[0], peers::scene.Jpivot[1], peers::scene.Jpivot[2]);
    Body::Rigid body(MassProperties(peers::scene.mass, c, I_pivot));
    top = MobilizedBody::Ball(matter.Ground(), Transform(), body, Transform());
    system.realizeTopology();
    initial = system.getDefaultState();
    top.setQ(initial, Vec4(1, 0, 0, 0));
    top.setU(initial, Vec3(peers::scene.w0[0], peers::scene.w0[1], peers::scene.w0[2]));
    system.realize(initial, Stage::Velocity);
  }
};

using Factory = std::function<std::unique_ptr<Integrator>(const System&)>;

}  // namespace

int main(int argc, char** argv) try {
  const char* usage =
      "simbody_heavy_top [--scene heavy_top|free_body] [--repeats N] [--budget S] [--settings acc,acc,...]\n"
      "  [--methods m,m]"
      "  [--reference FILE]  methods: RungeKuttaMerson, CPodesBDF, RungeKuttaFeldberg,\n"
      "  RungeKutta3, SemiExplicitEuler2 (default: all; accuracy 1e-3..1e-10)";
  auto opt = peers::parse_options(argc, argv, usage);
  if (opt.settings.empty())
    for (int e = 3; e <= 10; ++e) opt.settings.push_back(std::pow(10.0, -e));
  const auto q_ref = peers::load_reference(opt.reference);

  Model model;
  // Verify the model against the scene: energy of the initial state (the COM
  // starts at height 0, so it is all kinetic energy about the pivot).
  const double E0 = model.system.calcEnergy(model.initial);
  const double E0_analytic = peers::initial_energy();
  if (std::fabs(E0 - E0_analytic) > 1e-9 * E0_analytic) {
    std::fprintf(stderr, "simbody_heavy_top: initial energy %.12g, expected %.12g\n", E0, E0_analytic);
    return 1;
  }
  const Vec3 c(peers::scene.com[0], peers::scene.com[1], peers::scene.com[2]);
  const Vec3 com_G = model.top.findStationLocationInGround(model.initial, c);
  if ((com_G - c).norm() > 1e-15) throw std::runtime_error("COM not where the scene puts it");

  const std::vector<std::pair<std::string, Factory>> methods = {
      {"RungeKuttaMerson", [](const System& s) { return std::make_unique<RungeKuttaMersonIntegrator>(s); }},
      {"CPodesBDF", [](const System& s) { return std::make_unique<CPodesIntegrator>(s, CPodes::BDF, CPodes::Newton); }},
      {"RungeKuttaFeldberg", [](const System& s) { return std::make_unique<RungeKuttaFeldbergIntegrator>(s); }},
      {"RungeKutta3", [](const System& s) { return std::make_unique<RungeKutta3Integrator>(s); }},
      {"SemiExplicitEuler2", [](const System& s) { return std::make_unique<SemiExplicitEuler2Integrator>(s); }},
  };

  for (const auto& [name, make] : methods) {
    if (!peers::wanted(opt, name)) continue;
    for (double acc : opt.settings) {
      long long steps = 0, attempted = 0, realizations = 0, projections = 0;
      State final_state;
      auto run = [&] {
        auto integ = make(model.system);
        integ->setAccuracy(acc);
        integ->setFinalTime(peers::scene.t_end);  // land on t = 2 exactly, no interpolated output
        // No internal step limit to speak of: CPodes' default (mxstep 500 per
        // call) only makes stepTo() return early with a message on stderr.
        integ->setInternalStepLimit(100000000);
        integ->initialize(model.initial);
        while (integ->getTime() < peers::scene.t_end) {
          integ->stepTo(peers::scene.t_end);
          if (integ->isSimulationOver()) break;
        }
        steps = integ->getNumStepsTaken();
        attempted = integ->getNumStepsAttempted();
        realizations = integ->getNumRealizations();
        projections = integ->getNumProjections();
        final_state = integ->getState();
      };
      const auto [wall, n] = peers::median_wall(run, opt.repeats, opt.budget_s);
      if (std::fabs(final_state.getTime() - peers::scene.t_end) > 1e-12)
        std::fprintf(stderr, "simbody_heavy_top: %s acc %g stopped at t = %.17g\n", name.c_str(), acc,
                     final_state.getTime());
      model.system.realize(final_state, Stage::Velocity);
      const Quaternion qR = model.top.getBodyRotation(final_state).convertRotationToQuaternion();
      const double E = model.system.calcEnergy(final_state);

      peers::Row row;
      row.peer = "simbody";
      row.method = name;
      row.setting_kind = "accuracy";
      row.setting = acc;
      row.wall_s = wall;
      row.repeats = n;
      row.steps = steps;
      row.rhs_evals = realizations;
      row.q_final = peers::normalized({qR[0], qR[1], qR[2], qR[3]});
      if (q_ref) row.error_rad = peers::angle_between(*q_ref, row.q_final);
      row.extra = "\"steps_attempted\": " + std::to_string(attempted) +
                  ", \"projections\": " + std::to_string(projections) +
                  ", \"rel_energy_drift\": " + peers::num(std::fabs(E - E0) / E0);
      peers::print_row(row);
    }
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "simbody_heavy_top: %s\n", e.what());
  return 1;
}
