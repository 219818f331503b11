#pragma once
// The integrator a scene runs when neither its file nor the command line
// (nor a study's grid) names one: issue 23 item 4, chosen by measurement
// (bench/default_integrator.py, docs/benchmarks.md "Defaults chosen by
// measurement"). The rule, in order:
//   1. a scheme only IDA runs (index3, index2, ggl, baumgarte: the DAE
//      forms; solver/integrators.hpp) -> ida;
//   2. a stiff scene -> ida: with dt the output step, the fastest decay of
//      an overdamped element (c^2 >= 4 k m: (c + sqrt(c^2 - 4 k m)) / 2m,
//      c/m for a damper alone) times dt > kStiffDampingRateTimesOutputStep,
//      or sqrt(k/m) * dt > kStiffSpringRateTimesOutputStep, the largest
//      over springs (m the two
//      bodies' reduced mass, the ground's infinite) and torsional springs
//      and dampers (m the reduced moment of the two bodies about the joint
//      axis through their centres of mass: at most the true one, so the
//      rates are upper bounds);
//   3. otherwise arkode-erk (the scene's erk_method, Prince-Dormand 8(7) unless
//      named): the explicit table, on the scene's index1 or projection.
// A scene's coordinates, form and scheme are the file's (default
// quaternion/euler/ggl): the rule picks the integrator only.
#include <string>

#include "rigidae/model/scene.hpp"

namespace rigidae::settings {

// Limits of rule 2, from slider_mechanism over 0.5 s (dt = 0.01 s) with its
// spring made stiffer or its damper stronger (docs/benchmarks.md, "Defaults
// chosen by measurement"): with the damper overdamped, arkode-erk against
// IDA to equal error was 0.81x at decay x dt = 1.24, 3.8x at 125 and 509x
// at 12,500, so the damping limit lies between; with the stiffer spring
// (underdamped, excited) 0.29x at sqrt(k/m) dt = 11 and still cheaper at
// 112. The spring limit is set 10x above the largest case measured: where
// it crosses was not measured.
inline constexpr double kStiffDampingRateTimesOutputStep = 10.0;
inline constexpr double kStiffSpringRateTimesOutputStep = 1000.0;

// The fastest rates of a scene's force elements (1/s; 0 without any) and
// the spring or joint that sets each.
struct ForceRates {
  double spring = 0.0;   // sqrt(k/m)
  double damping = 0.0;  // the fast decay of an overdamped element, at most c/m (0 when all are underdamped)
  std::string spring_element, damping_element;
};
ForceRates force_rates(const Scene& scene);

struct DefaultIntegrator {
  std::string integrator;  // "ida" or "arkode-erk"
  std::string reason;      // why, for summary.json and the printed note
  ForceRates rates;
  double output_step = 0;  // dt, s
};

// The rule for this scene, whatever it names.
DefaultIntegrator default_integrator(const Scene& scene);

// Applies the rule when scene.solver.integrator_named is false (and records
// the reason in scene.solver.integrator_choice); otherwise records that the
// integrator was named. Called where the settings are final: at the end of
// the scene loader, after the command line's options, after a study's grid.
void resolve_integrator(Scene& scene);

}  // namespace rigidae::settings
