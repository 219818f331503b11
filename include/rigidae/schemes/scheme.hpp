#pragma once
// A constraint scheme: how the constraints enter the residual
// F(t, y, y') = 0 that IDA integrates. The constraints come in blocks, each
// of one kind (block_rows.hpp); a scheme states per kind which multiplier
// groups a block carries and which levels their rows combine (rows()):
//   lambda   force multipliers, G^T lambda in the dynamics M v' = f - G^T lambda
//   mu       kinematic multipliers, q' = N v - Phi_q^T mu (GGL-style)
// both algebraic (IDA id 0, and outside IDA's error test). The one
// assembler, MultibodyProblem (src/multibody/), reads a scheme through
// make_block_scheme (block_scheme.hpp): rows(), whether v leaves the error
// test (index 3) and whether the state is projected. The name, the note and
// the parameters go into the run's report.
#include <memory>
#include <string>
#include <vector>

#include "rigidae/coords/representation.hpp"
#include "rigidae/schemes/block_rows.hpp"
#include "rigidae/model/scene.hpp"

namespace rigidae {

// When a drifting scheme maps the state back onto the constraint manifold.
struct ProjectionPolicy {
  bool enabled = false;
  bool every_step = false;  // after every accepted step, or only when the drift passes threshold
  double threshold = 0.0;   // on |Phi| and |G v| (or |dPhi/dt|)
};

// A number a scheme runs with, for reports (e.g. Baumgarte's gain "a", 1/s).
struct SchemeParameter {
  std::string name;
  double value = 0.0;
};

class ConstraintScheme {
 public:
  virtual ~ConstraintScheme() = default;

  virtual std::string name() const = 0;
  // The rows this scheme writes for a block of each kind.
  virtual SchemeRows rows() const = 0;
  // True when the velocities must leave IDA's error test (index 3 with blocks
  // of this kind, where v is index 2); multipliers always leave it.
  virtual bool suppress_velocity_error_test(ConstraintKind /*kind*/) const { return false; }
  // The numbers this scheme runs with, as it uses them (defaults resolved).
  virtual std::vector<SchemeParameter> parameters() const { return {}; }
  // Whether and when the driver projects the state onto the manifold.
  virtual ProjectionPolicy projection() const { return {}; }
  // A note for the report when the scheme does something unusual for this
  // representation. Without constraints (Euler angles) every scheme is the
  // same ODE, and the note says so; otherwise it is constrained_note().
  std::string note(const Representation& rep) const;

 protected:
  // The note for a representation with constraints (empty by default).
  virtual std::string constrained_note(const Representation& /*rep*/) const { return {}; }
};

// What the schemes read of a run's settings, defaults resolved: a scheme's
// factory receives this, not the scene.
struct SchemeSettings {
  double baumgarte_a = 1.0, baumgarte_b = 1.0;  // 1/s (baumgarte)
  bool project_every_step = false;              // projection
  double projection_threshold = 0.0;            // projection: on |Phi| and |G v| (or |dPhi/dt|)
};
// A scene's, with the defaults of baumgarte_gains and projection_threshold (model/scene.hpp).
SchemeSettings scheme_settings(const Scene& scene);

// The registered schemes, by name.
std::unique_ptr<ConstraintScheme> make_scheme(const std::string& name, const SchemeSettings& settings);
// Every registered name, in the registry's order.
std::vector<std::string> scheme_names();

}  // namespace rigidae
