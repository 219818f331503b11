// Projection: a drifting index-1 form whose state the driver maps back onto
// the constraint manifold, then hands back to IDA (IDAReInit).
//
// Rows: those of index1 (Force kind: G v' = gamma; Kinematic kind: the ODE
// q' = N v, M v' = f). After a step whose drift passes the threshold (or
// after every step), the driver projects:
//   q onto the manifold (normalised quaternion, polar factor of R), then
//   v onto G(q) v = 0 in the metric of M (Force kind; the least change of
//   kinetic energy), and restarts IDA from the projected, consistent state.
// The restart is the hidden cost: IDA forgets its history and begins again
// at order 1, which shows in the steps and the restart counter.
#include <fmt/format.h>

#include "factories.hpp"

namespace rigidae::schemes {

namespace {

class ProjectionScheme final : public ConstraintScheme {
 public:
  explicit ProjectionScheme(const ProjectionPolicy& p) : policy_(p) {}

  std::string name() const override { return "projection"; }
  // The rows of index1: Force: lambda rows G v' - gamma. Kinematic: no rows.
  SchemeRows rows() const override { return {{true, false, {0.0, 0.0, 1.0}, {}}, {}}; }
  ProjectionPolicy projection() const override { return policy_; }
  std::vector<SchemeParameter> parameters() const override { return {{"threshold", policy_.threshold}}; }
  std::string constrained_note(const Representation& /*rep*/) const override {
    const std::string when = policy_.every_step ? "after every step"
                                                : fmt::format("when the drift exceeds {:g}", policy_.threshold);
    return "index-1 rows; the state is projected onto the manifold " + when + " and IDA restarts at order 1";
  }

 private:
  ProjectionPolicy policy_;
};

}  // namespace

std::unique_ptr<ConstraintScheme> make_projection(const SchemeSettings& settings) {
  ProjectionPolicy p;
  p.enabled = true;
  p.every_step = settings.project_every_step;
  p.threshold = settings.projection_threshold;
  return std::make_unique<ProjectionScheme>(p);
}

}  // namespace rigidae::schemes
