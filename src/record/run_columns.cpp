// The column set a system's run records (see record/run_columns.hpp): chosen
// here, once, from the model.
#include "rigidae/record/run_columns.hpp"

#include "mechanism_columns.hpp"
#include "one_body_columns.hpp"

namespace rigidae {

bool records_one_body_columns(const MultibodySpec& spec) {
  // One-body files keep the one-body names, which the tools, the Python
  // module and users' scripts read (docs/architecture.md).
  return spec.one_body_scene;
}

std::string body_column_prefix(const MultibodySpec& spec, std::size_t body) {
  return records_one_body_columns(spec) ? std::string() : spec.bodies.at(body).name + ".";
}

std::unique_ptr<RunColumns> make_run_columns(multibody::MultibodyProblem& system, const Scene& scene) {
  if (records_one_body_columns(system.spec())) return std::make_unique<OneBodyColumns>(system, scene);
  return std::make_unique<MechanismColumns>(system, scene);
}

}  // namespace rigidae
