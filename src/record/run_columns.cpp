// The column set a system's run records (see record/run_columns.hpp): chosen
// here, once, from the model.
#include "rigidae/record/run_columns.hpp"

#include "mechanism_columns.hpp"
#include "one_body_columns.hpp"

namespace rigidae {

std::unique_ptr<RunColumns> make_run_columns(multibody::MultibodyProblem& system, const Scene& scene) {
  if (system.spec().one_body_scene) return std::make_unique<OneBodyColumns>(system, scene);
  return std::make_unique<MechanismColumns>(system, scene);
}

}  // namespace rigidae
