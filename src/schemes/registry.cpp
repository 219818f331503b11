// The table of constraint schemes, by name.
#include <array>
#include <string_view>
#include <tuple>

#include "factories.hpp"
#include "rigidae/core/error.hpp"

namespace rigidae {

namespace {

struct SchemeEntry {
  std::string_view name;
  std::unique_ptr<ConstraintScheme> (*make)(const SchemeSettings&);
};

// In the order a comparison lists them: from the raw index-3 form down the
// index hierarchy, then the stabilised forms.
constexpr SchemeEntry kSchemes[] = {
    {"index3", schemes::make_index3},
    {"index2", schemes::make_index2},
    {"index1", schemes::make_index1},
    {"baumgarte", schemes::make_baumgarte},
    {"ggl", schemes::make_ggl},
    {"projection", schemes::make_projection},
};

}  // namespace

std::vector<std::string> scheme_names() {
  std::vector<std::string> names;
  for (const auto& e : kSchemes) names.emplace_back(e.name);
  return names;
}

SchemeSettings scheme_settings(const Scene& scene) {
  SchemeSettings s;
  std::tie(s.baumgarte_a, s.baumgarte_b) = baumgarte_gains(scene);
  s.project_every_step = scene.formulation.projection.every_step;
  s.projection_threshold = projection_threshold(scene);
  return s;
}

std::unique_ptr<ConstraintScheme> make_scheme(const std::string& name, const SchemeSettings& settings) {
  for (const auto& e : kSchemes)
    if (e.name == name) return e.make(settings);
  std::string valid;
  for (const auto& e : kSchemes) valid += (valid.empty() ? "" : ", ") + std::string(e.name);
  throw InputError("unknown scheme '" + name + "'; valid schemes: " + valid);
}

}  // namespace rigidae
