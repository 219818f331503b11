#pragma once
// A validated scene: plain, immutable physics and run settings.
//
// Produced only by io::load_scene (which checks every value and reports
// file:line:col on failure) or built directly in tests. Units are SI and
// angles radians throughout.
#include <optional>
#include <string>

#include "rigidae/core/types.hpp"
#include "rigidae/so3/euler_sequence.hpp"

namespace rigidae {

enum class Support { FixedPoint, Free };
enum class Coordinates { EulerAngles, Quaternion, Linear };
enum class Equations { Lagrange, Euler };
enum class AngularVelocityFrame { Body, Space };

struct RigidBodySpec {
  double mass = 1.0;                    // kg, > 0
  Mat3 inertia_com = Mat3::Identity();  // kg m^2 about the centre of mass, body axes, SPD
  Vec3 com_B = Vec3::Zero();            // m, centre of mass in the body frame,
                                        // measured from the body origin (the fixed point of a top)
};

struct EulerChartSpec {
  // Initial sequence; empty optional = pick the most regular one at t_start.
  std::optional<so3::EulerSequence> sequence;
  bool switching = true;           // change chart when the margin falls below the threshold
  double switch_threshold = 0.1;   // margin |sin b| or |cos b| that triggers a switch, in (0, 1)
};

struct Formulation {
  Coordinates coordinates = Coordinates::Quaternion;
  Equations equations = Equations::Lagrange;
  std::string scheme = "ggl";  // name in the scheme registry
  EulerChartSpec euler;        // used only with Coordinates::EulerAngles
};

struct SolverSettings {
  double rtol = 1e-8;            // in (0, 1)
  double atol = 1e-8;            // > 0, absolute tolerance of coordinates and velocities
  long max_steps = 10'000'000;   // internal IDA steps over the whole run
  int max_order = 5;             // BDF order limit, 1..5
  double initial_step = 0.0;     // 0: estimated from the start's second derivative
  // Iteration matrix: "central" (rigidae's differences, accurate to ~1e-11)
  // or "ida_dq" (IDA's own forward difference quotients).
  std::string jacobian = "central";
};

struct TimeGrid {
  double start = 0.0;          // s
  double end = 1.0;            // s, > start
  double output_step = 0.01;   // s, > 0; grid = start, start + k step, ..., end (end always included)
};

struct Scene {
  std::string source;       // file the scene came from ("" when built in code)
  std::string name;         // short name for reports
  std::string description;  // free text
  RigidBodySpec body;
  Support support = Support::FixedPoint;
  Vec3 gravity_W = Vec3(0, 0, -9.81);  // m/s^2, space frame
  Mat3 R0_WB = Mat3::Identity();       // initial orientation, an exact rotation after loading
  Vec3 omega0_B = Vec3::Zero();        // rad/s, initial angular velocity in body components
  TimeGrid time;
  Formulation formulation;
  SolverSettings solver;
};

}  // namespace rigidae
