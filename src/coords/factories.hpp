#pragma once
// One factory per representation file; the table in registry.cpp lists them.
#include <memory>

#include "rigidae/coords/representation.hpp"

namespace rigidae::coords {

std::unique_ptr<Representation> make_euler_angles_lagrange(const Scene& scene, const RigidBodyModel& body);
std::unique_ptr<Representation> make_euler_angles_euler(const Scene& scene, const RigidBodyModel& body);
std::unique_ptr<Representation> make_quaternion_lagrange(const Scene& scene, const RigidBodyModel& body);
std::unique_ptr<Representation> make_quaternion_euler(const Scene& scene, const RigidBodyModel& body);
std::unique_ptr<Representation> make_linear_lagrange(const Scene& scene, const RigidBodyModel& body);
std::unique_ptr<Representation> make_linear_euler(const Scene& scene, const RigidBodyModel& body);

}  // namespace rigidae::coords
