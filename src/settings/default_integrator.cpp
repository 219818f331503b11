// The default integrator rule (see default_integrator.hpp for the rule and
// docs/benchmarks.md for the measurement behind it).
//
// Rates of the force elements (1/s), each an upper bound on the magnitude of
// the fastest eigenvalue that element adds to the linearised motion:
//   linear spring-damper   sqrt(k / m), c / m,   1/m = 1/m_a + 1/m_b (ground: 1/m = 0)
//   torsional spring       sqrt(k / I), c / I,   1/I = 1/I_a + 1/I_b, I a body's moment
//                                                about the joint axis through its centre of mass
// An undamped oscillator has eigenvalues +-i sqrt(k/m); an overdamped one's
// fast eigenvalue tends to -c/m. Joints and gravity add no rate here: the
// shipped mechanisms without springs are measured non-stiff.
#include "rigidae/settings/default_integrator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

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

// The rate of a spring-damper of stiffness k and damping c on inverse inertia w.
double element_rate(double k, double c, double w) { return std::max(std::sqrt(std::max(k, 0.0) * w), c * w); }

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

double fastest_force_rate(const Scene& scene, std::string* element) {
  if (element) element->clear();
  if (!scene.multibody) return 0.0;
  const MultibodySpec& spec = *scene.multibody;
  double fastest = 0.0;
  auto consider = [&](double rate, const std::string& name) {
    if (rate > fastest) {
      fastest = rate;
      if (element) *element = name;
    }
  };
  for (const SpringSpec& s : spec.springs)
    consider(element_rate(s.stiffness, s.damping, inverse_mass(spec, s.body_a) + inverse_mass(spec, s.body_b)),
             s.name);
  for (const JointSpec& j : spec.joints)
    if (j.torsion_stiffness > 0.0 || j.torsion_damping > 0.0)
      consider(element_rate(j.torsion_stiffness, j.torsion_damping,
                            inverse_moment_about(spec, j.body_a, j.axis_a) + inverse_moment_about(spec, j.body_b, j.axis_b)),
               j.name);
  return fastest;
}

DefaultIntegrator default_integrator(const Scene& scene) {
  DefaultIntegrator d;
  d.fastest_rate = fastest_force_rate(scene, &d.fastest_element);
  d.output_step = output_step(scene);
  const std::string& scheme = scene.formulation.scheme;
  if (!explicit_runs(scheme)) {
    d.integrator = kIda;
    d.reason = fmt::format("default for scheme {}, which only IDA runs", scheme);
    return d;
  }
  const double product = d.fastest_rate * d.output_step;
  if (product > kStiffRateTimesOutputStep) {
    d.integrator = kIda;
    d.reason = fmt::format("default for a stiff scene: {} sets a rate of {:.3g} 1/s, {:.3g} x the output step {:g} s "
                           "> {:g}",
                           d.fastest_element, d.fastest_rate, product, d.output_step, kStiffRateTimesOutputStep);
    return d;
  }
  d.integrator = kExplicit;
  d.reason = d.fastest_rate > 0.0
                 ? fmt::format("default for a non-stiff scene with scheme {}: its fastest rate {:.3g} 1/s ({}) x the "
                               "output step {:g} s = {:.3g} <= {:g}",
                               scheme, d.fastest_rate, d.fastest_element, d.output_step, product,
                               kStiffRateTimesOutputStep)
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
