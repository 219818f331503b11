#pragma once
// One factory per representation file; the table in registry.cpp lists them.
// Each receives the body and the chart to start in (used by representations
// with charts only), nothing else of the scene.
#include <memory>

#include "rigidae/coords/representation.hpp"
#include "rigidae/so3/euler_sequence.hpp"

namespace rigidae::coords {

std::unique_ptr<Representation> make_euler_angles_lagrange(const RigidBodyModel& body, const so3::EulerSequence& start_chart);
std::unique_ptr<Representation> make_euler_angles_euler(const RigidBodyModel& body, const so3::EulerSequence& start_chart);
std::unique_ptr<Representation> make_quaternion_lagrange(const RigidBodyModel& body, const so3::EulerSequence& start_chart);
std::unique_ptr<Representation> make_quaternion_euler(const RigidBodyModel& body, const so3::EulerSequence& start_chart);
std::unique_ptr<Representation> make_linear_lagrange(const RigidBodyModel& body, const so3::EulerSequence& start_chart);
std::unique_ptr<Representation> make_linear_euler(const RigidBodyModel& body, const so3::EulerSequence& start_chart);

}  // namespace rigidae::coords
