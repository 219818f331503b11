// A registered scheme's rows per block kind, for the multibody assembler
// (see block_scheme.hpp): read from the scheme itself, not restated.
#include "rigidae/multibody/block_scheme.hpp"

#include "rigidae/schemes/scheme.hpp"

namespace rigidae::multibody {

BlockScheme make_block_scheme(const std::string& name, double a, double b) {
  SchemeSettings settings;
  settings.baumgarte_a = a;
  settings.baumgarte_b = b;
  const std::unique_ptr<ConstraintScheme> scheme = make_scheme(name, settings);
  const SchemeRows rows = scheme->rows();
  BlockScheme s;
  s.name = scheme->name();
  s.force = rows.force;
  s.kinematic = rows.kinematic;
  s.index3 = scheme->suppress_velocity_error_test(ConstraintKind::Force);
  s.projection = scheme->projection().enabled;
  return s;
}

}  // namespace rigidae::multibody
