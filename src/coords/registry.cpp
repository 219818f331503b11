// The table of representations: one row per (coordinates, equations).
#include <array>

#include "factories.hpp"
#include "rigidae/core/error.hpp"

namespace rigidae {

namespace {

struct RepresentationEntry {
  Coordinates coordinates;
  Equations equations;
  std::unique_ptr<Representation> (*make)(const Scene&, const RigidBodyModel&);
};

constexpr std::array<RepresentationEntry, 6> kRepresentations{{
    {Coordinates::EulerAngles, Equations::Lagrange, coords::make_euler_angles_lagrange},
    {Coordinates::EulerAngles, Equations::Euler, coords::make_euler_angles_euler},
    {Coordinates::Quaternion, Equations::Lagrange, coords::make_quaternion_lagrange},
    {Coordinates::Quaternion, Equations::Euler, coords::make_quaternion_euler},
    {Coordinates::Linear, Equations::Lagrange, coords::make_linear_lagrange},
    {Coordinates::Linear, Equations::Euler, coords::make_linear_euler},
}};

}  // namespace

std::unique_ptr<Representation> make_representation(const Scene& scene, const RigidBodyModel& body) {
  for (const auto& e : kRepresentations)
    if (e.coordinates == scene.formulation.coordinates && e.equations == scene.formulation.equations)
      return e.make(scene, body);
  throw InputError("no representation for coordinates '" + to_string(scene.formulation.coordinates) +
                   "' with equations '" + to_string(scene.formulation.equations) + "'");
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
