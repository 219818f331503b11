// The default integrator rule (see default_integrator.hpp for the rule and
// docs/benchmarks.md for the measurement behind it).
//
// Rates of the force elements (1/s), each an upper bound on the magnitude of
// an eigenvalue that element adds to the linearised motion:
//   linear spring-damper  sqrt(k/m); overdamped (c^2 >= 4km), also the fast
//                         decay (c + sqrt(c^2 - 4km)) / 2m <= c/m;
//                         1/m = 1/m_a + 1/m_b (the ground: 0)
//   torsional spring or   the same with I for m: 1/I = 1/I_a + 1/I_b, I a
//   damper (revolute)     body's moment about the joint axis through its
//                         centre of mass
// An undamped oscillator has eigenvalues +-i sqrt(k/m), which an explicit
// table must resolve only as far as the motion excites them (an excited one
// every integrator must resolve); an overdamped one's fast eigenvalue, up to
// -c/m, is a decaying mode that bounds an explicit table's step for the
// whole run: the classical stiff case. Hence two limits (measured:
// docs/benchmarks.md). Joints and gravity add no rate here: the shipped
// mechanisms without springs are measured non-stiff.
#include "rigidae/settings/default_integrator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "rigidae/model/one_body_system.hpp"
#include "rigidae/solver/integrators.hpp"

namespace rigidae::settings {

namespace {

constexpr const char* kIda = "ida";
constexpr const char* kExplicit = "arkode-erk";

// 1/m of a body (0 for the ground).
double inverse_mass(const MultibodySpec& spec, int body) {
  return body == kGround ? 0.0 : 1.0 / spec.bodies[static_cast<std::size_t>(body)].mass;
}

// 1/I with I the body's moment of inertia about the joint axis through its
// centre of mass (0 for the ground; a particle has no rotation and no
// torsional spring acts on it). The parallel-axis term and the bodies
// beyond are left out: I is at most the true one, the rate at least.
double inverse_moment_about(const MultibodySpec& spec, int body, const Vec3& axis_B) {
  if (body == kGround) return 0.0;
  const BodySpec& b = spec.bodies[static_cast<std::size_t>(body)];
  if (b.particle) return 0.0;
  const double moment = axis_B.dot(b.inertia_com * axis_B);
  return moment > 0.0 ? 1.0 / moment : 0.0;
}

// The time between outputs: the even grid's step, or the span over the given times.
double output_step(const Scene& scene) {
  const TimeGrid& g = scene.time;
  if (!g.output_times.empty()) return (g.end - g.start) / static_cast<double>(g.output_times.size());
  return g.output_step;
}

bool explicit_runs(const std::string& scheme) {
  const IntegratorInfo& erk = find_integrator(kExplicit);
  return std::find(erk.schemes.begin(), erk.schemes.end(), scheme) != erk.schemes.end();
}

}  // namespace

ForceRates force_rates(const Scene& scene) {
  ForceRates r;
  // Read off the system the scene runs as (a one-body scene: one pivoted
  // body, no springs or joints, hence no rate).
  const Scene system = as_system(scene);
  const MultibodySpec& spec = *system.multibody;
  // An element of stiffness k and damping c on inverse inertia w: x'' + c w x' + k w x = 0, eigenvalues
  // (-c w +- sqrt(c^2 w^2 - 4 k w)) / 2. Overdamped (c^2 w >= 4 k), the fast one decays at
  // (c w + sqrt(c^2 w^2 - 4 k w)) / 2 (c w for a damper alone); underdamped, the pair oscillates at
  // |lambda| = sqrt(k w) and decays at c w / 2 < sqrt(k w): the spring's rate covers it.
  auto consider = [&](double k, double c, double w, const std::string& name) {
    k = std::max(k, 0.0), c = std::max(c, 0.0);
    const double spring = std::sqrt(k * w);
    const double damping = c * c * w >= 4 * k ? 0.5 * (c * w + std::sqrt(c * c * w * w - 4 * k * w)) : 0.0;
    if (spring > r.spring) r.spring = spring, r.spring_element = name;
    if (damping > r.damping) r.damping = damping, r.damping_element = name;
  };
  for (const SpringSpec& s : spec.springs)
    consider(s.stiffness, s.damping, inverse_mass(spec, s.body_a) + inverse_mass(spec, s.body_b), s.name);
  for (const JointSpec& j : spec.joints)
    if (j.torsion_stiffness > 0.0 || j.torsion_damping > 0.0)
      consider(j.torsion_stiffness, j.torsion_damping,
               inverse_moment_about(spec, j.body_a, j.axis_a) + inverse_moment_about(spec, j.body_b, j.axis_b), j.name);
  return r;
}

DefaultIntegrator default_integrator(const Scene& scene) {
  DefaultIntegrator d;
  d.rates = force_rates(scene);
  d.output_step = output_step(scene);
  const std::string& scheme = scene.formulation.scheme;
  if (!explicit_runs(scheme)) {
    d.integrator = kIda;
    d.reason = fmt::format("default for scheme {}, which only IDA runs", scheme);
    return d;
  }
  const double damping = d.rates.damping * d.output_step, spring = d.rates.spring * d.output_step;
  if (damping > kStiffDampingRateTimesOutputStep) {
    d.integrator = kIda;
    d.reason = fmt::format("default for a stiff scene: {} is overdamped, its fast mode decays at {:.3g} 1/s, {:.3g} x "
                           "the output step {:g} s > {:g}",
                           d.rates.damping_element, d.rates.damping, damping, d.output_step,
                           kStiffDampingRateTimesOutputStep);
    return d;
  }
  if (spring > kStiffSpringRateTimesOutputStep) {
    d.integrator = kIda;
    d.reason = fmt::format("default for a stiff scene: {} sets sqrt(k/m) = {:.3g} 1/s, {:.3g} x the output step {:g} "
                           "s > {:g}",
                           d.rates.spring_element, d.rates.spring, spring, d.output_step,
                           kStiffSpringRateTimesOutputStep);
    return d;
  }
  d.integrator = kExplicit;
  d.reason = d.rates.spring > 0.0 || d.rates.damping > 0.0
                 ? fmt::format("default for a non-stiff scene with scheme {}: the fastest decay x the output step "
                               "{:.3g} <= {:g}, sqrt(k/m) x it {:.3g} <= {:g}",
                               scheme, damping, kStiffDampingRateTimesOutputStep, spring,
                               kStiffSpringRateTimesOutputStep)
                 : fmt::format("default for a non-stiff scene with scheme {}: no spring or damper", scheme);
  return d;
}

void resolve_integrator(Scene& scene) {
  if (scene.solver.integrator_named) {
    scene.solver.integrator_choice = "named";
    return;
  }
  const DefaultIntegrator d = default_integrator(scene);
  scene.solver.integrator = d.integrator;
  scene.solver.integrator_choice = d.reason;
}

}  // namespace rigidae::settings
