#pragma once
// Which coordinates describe a body's orientation: the name of a row of the
// table of representations (src/coords/registry.cpp), e.g. "quaternion".
//
// The model does not list the coordinates: the registry does, and the scene
// key formulation.coordinates, --coordinates, a multibody body's
// `coordinates` and compare's combinations all take their valid names from
// it (coordinates_names() in coords/representation.hpp). A new
// representation is therefore a registry row, not a value here.
//
// A Coordinates read from a file or the command line was checked against the
// registry by the settings table; one built in code is checked when its
// representation is made (make_representation throws InputError listing the
// valid names).
#include <string>
#include <string_view>

namespace rigidae {

class Coordinates {
 public:
  // The scenes' default: quaternions.
  Coordinates() : name_("quaternion") {}
  explicit Coordinates(std::string_view name) : name_(name) {}

  // The registry name, as users write it and reports print it.
  const std::string& name() const { return name_; }

  friend bool operator==(const Coordinates& a, const Coordinates& b) { return a.name_ == b.name_; }
  friend bool operator!=(const Coordinates& a, const Coordinates& b) { return !(a == b); }

  // Coordinates that code asks for on purpose (the tight reference run is in
  // quaternions, its check in Euler angles; tests). Not the list of
  // coordinates, which is the registry's: a new representation adds nothing
  // here. A test checks that each names a registry row.
  static const Coordinates EulerAngles;
  static const Coordinates Quaternion;
  static const Coordinates Linear;

 private:
  std::string name_;
};

inline const Coordinates Coordinates::EulerAngles{"euler"};
inline const Coordinates Coordinates::Quaternion{"quaternion"};
inline const Coordinates Coordinates::Linear{"linear"};

}  // namespace rigidae
