// The table of representations, by name: one row per (coordinates, equations).
#include <array>
#include <string_view>

#include "factories.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/so3/euler_sequence.hpp"

namespace rigidae {

namespace {

struct RepresentationEntry {
  std::string_view name;  // "coordinates/equations", as Representation::name() says
  std::unique_ptr<Representation> (*make)(const RigidBodyModel&, const so3::EulerSequence&);
};

constexpr RepresentationEntry kRepresentations[] = {
    {"euler/lagrange", coords::make_euler_angles_lagrange},
    {"euler/euler", coords::make_euler_angles_euler},
    {"quaternion/lagrange", coords::make_quaternion_lagrange},
    {"quaternion/euler", coords::make_quaternion_euler},
    {"linear/lagrange", coords::make_linear_lagrange},
    {"linear/euler", coords::make_linear_euler},
};

}  // namespace

std::vector<std::string> representation_names() {
  std::vector<std::string> names;
  for (const auto& e : kRepresentations) names.emplace_back(e.name);
  return names;
}

std::unique_ptr<Representation> make_representation(const std::string& name, const RigidBodyModel& body,
                                                    const so3::EulerSequence& start_chart) {
  for (const auto& e : kRepresentations)
    if (e.name == name) return e.make(body, start_chart);
  std::string valid;
  for (const auto& e : kRepresentations) valid += (valid.empty() ? "" : ", ") + std::string(e.name);
  throw InputError("unknown representation '" + name + "'; valid representations: " + valid);
}

std::string representation_name(Coordinates c, Equations e) { return to_string(c) + "/" + to_string(e); }

std::unique_ptr<Representation> make_representation(const Scene& scene, const RigidBodyModel& body) {
  // The chart to start in: the scene's sequence if it names one, else the
  // most regular at the initial orientation.
  const so3::EulerSequence start =
      scene.formulation.euler.sequence.value_or(so3::most_regular_sequence(scene.R0_WB));
  return make_representation(representation_name(scene.formulation.coordinates, scene.formulation.equations), body,
                             start);
}

std::string to_string(Coordinates c) {
  switch (c) {
    case Coordinates::EulerAngles: return "euler";
    case Coordinates::Quaternion: return "quaternion";
    case Coordinates::Linear: return "linear";
  }
  return "?";
}

std::string to_string(Equations e) { return e == Equations::Lagrange ? "lagrange" : "euler"; }

}  // namespace rigidae
