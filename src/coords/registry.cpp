// The table of coordinate representations, by name: one row per set of
// coordinates, with what it is (for --help) and its factory in each form.
// Every list of coordinates a user can name is read from this table: the
// scene key formulation.coordinates and --coordinates (settings/table.cpp),
// a multibody body's `coordinates`, compare's combinations, the tests' loops.
#include <string_view>

#include "factories.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/so3/euler_sequence.hpp"

namespace rigidae {

namespace {

using Factory = std::unique_ptr<Representation> (*)(const RigidBodyModel&, const so3::EulerSequence&);

struct CoordinatesEntry {
  std::string_view name;  // formulation.coordinates; "<name>/<form>" names a representation
  std::string_view what;  // one phrase for --help: what the coordinates are, how many, their constraints
  bool constrained;       // carries position constraints (checked against nc() by the tests)
  Factory lagrange, euler;
};

constexpr CoordinatesEntry kCoordinates[] = {
    {"euler", "Euler angles (3, singular charts switched during the run)", false, coords::make_euler_angles_lagrange,
     coords::make_euler_angles_euler},
    {"quaternion", "unit quaternions (4, 1 constraint)", true, coords::make_quaternion_lagrange,
     coords::make_quaternion_euler},
    {"linear", "the 9 entries of R (6 constraints)", true, coords::make_linear_lagrange, coords::make_linear_euler},
};

const CoordinatesEntry* find(std::string_view name) {
  for (const auto& e : kCoordinates)
    if (e.name == name) return &e;
  return nullptr;
}

const CoordinatesEntry& entry(const Coordinates& c) {
  if (const CoordinatesEntry* e = find(c.name())) return *e;
  std::string valid;
  for (const auto& e : kCoordinates) valid += (valid.empty() ? "" : ", ") + std::string(e.name);
  throw InputError("unknown coordinates '" + c.name() + "'; valid coordinates: " + valid);
}

}  // namespace

std::vector<std::string> coordinates_names() {
  std::vector<std::string> names;
  for (const auto& e : kCoordinates) names.emplace_back(e.name);
  return names;
}

std::vector<Coordinates> all_coordinates() {
  std::vector<Coordinates> all;
  for (const auto& e : kCoordinates) all.emplace_back(e.name);
  return all;
}

bool has_constraints(const Coordinates& c) { return entry(c).constrained; }

std::string coordinates_help() {
  std::string s;
  const std::size_t n = std::size(kCoordinates);
  for (std::size_t i = 0; i < n; ++i)
    s += std::string(i == 0 ? "" : i + 1 == n ? " or " : ", ") + std::string(kCoordinates[i].what);
  return s;
}

std::vector<std::string> representation_names() {
  std::vector<std::string> names;
  for (const auto& e : kCoordinates)
    for (Equations q : {Equations::Lagrange, Equations::Euler})
      names.push_back(representation_name(Coordinates(e.name), q));
  return names;
}

std::unique_ptr<Representation> make_representation(const std::string& name, const RigidBodyModel& body,
                                                    const so3::EulerSequence& start_chart) {
  for (const auto& e : kCoordinates)
    for (Equations q : {Equations::Lagrange, Equations::Euler})
      if (representation_name(Coordinates(e.name), q) == name)
        return (q == Equations::Lagrange ? e.lagrange : e.euler)(body, start_chart);
  std::string valid;
  for (const std::string& n : representation_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw InputError("unknown representation '" + name + "'; valid representations: " + valid);
}

std::string representation_name(const Coordinates& c, Equations e) { return to_string(c) + "/" + to_string(e); }

std::unique_ptr<Representation> make_representation(const Scene& scene, const RigidBodyModel& body) {
  // The chart to start in: the scene's sequence if it names one, else the
  // most regular at the initial orientation.
  const so3::EulerSequence start =
      scene.formulation.euler.sequence.value_or(so3::most_regular_sequence(scene.R0_WB));
  return make_representation(representation_name(scene.formulation.coordinates, scene.formulation.equations), body,
                             start);
}

std::string to_string(const Coordinates& c) { return c.name(); }

std::string to_string(Equations e) { return e == Equations::Lagrange ? "lagrange" : "euler"; }

}  // namespace rigidae
