#pragma once
// The integrator a scene runs when neither its file nor the command line
// (nor a study's grid) names one: issue 23 item 4, chosen by measurement
// (bench/default_integrator.py, docs/benchmarks.md "Defaults chosen by
// measurement"). The rule, in order:
//   1. a scheme only IDA runs (index3, index2, ggl, baumgarte: the DAE
//      forms; solver/integrators.hpp) -> ida;
//   2. a stiff scene -> ida: the fastest rate of its force elements, lambda,
//      times the output step dt exceeds kStiffRateTimesOutputStep, where
//      lambda is the largest over springs of sqrt(k / m) and c / m (m the
//      two bodies' reduced mass, the ground's infinite) and over torsional
//      springs of sqrt(k / I) and c / I (I the reduced moment of the two
//      bodies about the joint axis through their centres of mass: at most
//      the true one, so the rate is an upper bound);
//   3. otherwise arkode-erk (the scene's erk_method, Fehlberg 7(8) unless
//      named): the explicit table, on the scene's index1 or projection.
// A scene's coordinates, form and scheme are the file's (default
// quaternion/euler/ggl): the rule picks the integrator only.
#include <string>

#include "rigidae/model/scene.hpp"

namespace rigidae::settings {

// lambda * dt above which a scene counts as stiff (rule 2). Measured on
// slider_mechanism with its spring made stiffer (docs/benchmarks.md).
inline constexpr double kStiffRateTimesOutputStep = 10.0;

struct DefaultIntegrator {
  std::string integrator;   // "ida" or "arkode-erk"
  std::string reason;       // why, for summary.json and the printed note
  double fastest_rate = 0;  // lambda, 1/s (0: no spring or damper)
  std::string fastest_element;  // the spring or joint that sets it ("" when none)
  double output_step = 0;   // dt, s
};

// lambda and the element that sets it (rule 2), from the scene's springs and
// torsional springs; 0 for a scene without any.
double fastest_force_rate(const Scene& scene, std::string* element = nullptr);

// The rule for this scene, whatever it names.
DefaultIntegrator default_integrator(const Scene& scene);

// Applies the rule when scene.solver.integrator_named is false (and records
// the reason in scene.solver.integrator_choice); otherwise records that the
// integrator was named. Called where the settings are final: at the end of
// the scene loader, after the command line's options, after a study's grid.
void resolve_integrator(Scene& scene);

}  // namespace rigidae::settings
