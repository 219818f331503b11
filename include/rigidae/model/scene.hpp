#pragma once
// A validated scene: plain, immutable physics and run settings.
//
// Produced only by io::load_scene (which checks every value and reports
// file:line:col on failure) or built directly in tests. Units are SI and
// angles radians throughout.
#include <algorithm>
#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "rigidae/core/run_settings.hpp"
#include "rigidae/core/types.hpp"
#include "rigidae/model/coordinates.hpp"
#include "rigidae/model/multibody_spec.hpp"
#include "rigidae/so3/euler_sequence.hpp"

namespace rigidae {

enum class Support { FixedPoint, Free };
enum class Equations { Lagrange, Euler };
enum class AngularVelocityFrame { Body, Space };
// What accuracy is measured against: the closed-form solution (exact/) when
// the scene has one (Auto), insisted on (Exact), or a tight run (Tight).
enum class ReferenceKind { Auto, Exact, Tight };

struct RigidBodySpec {
  double mass = 1.0;                    // kg, > 0
  Mat3 inertia_com = Mat3::Identity();  // kg m^2 about the centre of mass, body axes, SPD
  Vec3 com_B = Vec3::Zero();            // m, centre of mass in the body frame,
                                        // measured from the body origin (the fixed point of a top)
  std::vector<VisualShape> visuals;     // how to draw it (none: its inertia ellipsoid); body frame
};

struct EulerChartSpec {
  // Initial sequence; empty optional = pick the most regular one at t_start.
  std::optional<so3::EulerSequence> sequence;
  bool switching = true;           // change chart when the margin falls below the threshold
  double switch_threshold = 0.1;   // margin |sin b| or |cos b| that triggers a switch, in (0, 1)
};

// Baumgarte's feedback Phi'' + 2 a Phi' + b^2 Phi = 0 (Force kind) and
// Phi' + a Phi = 0 (Kinematic kind, where the constraint is first order).
// Unset gains default to the initial angular speed (see baumgarte_gains).
struct BaumgarteGains {
  std::optional<double> a;  // 1/s, >= 0: damping of the drift
  std::optional<double> b;  // 1/s, >= 0: stiffness of the drift
};

// When the projection scheme maps the state back onto the manifold.
struct ProjectionSpec {
  bool every_step = false;          // true: after every step; false: when the drift passes the threshold
  std::optional<double> threshold;  // on |Phi| and on |G v| (or |dPhi/dt|); unset: see projection_threshold
};

struct Formulation {
  Coordinates coordinates = Coordinates::Quaternion;  // a name in the representation registry
  Equations equations = Equations::Lagrange;
  std::string scheme = "ggl";  // name in the scheme registry
  EulerChartSpec euler;        // used only with Coordinates::EulerAngles
  BaumgarteGains baumgarte;    // used only by the baumgarte scheme
  ProjectionSpec projection;   // used only by the projection scheme
};

struct Scene {
  std::string source;       // file the scene came from ("" when built in code)
  // The schema_version of the scene file, as the loader read it: 1 (one
  // body), 2 (bodies and joints, a [urdf] scene among them). A bare .urdf
  // file has no version of its own: it is read as a scene of bodies and
  // joints and recorded as 2. 0: built in code, from no file.
  int schema_version = 0;
  std::string name;         // short name for reports
  std::string description;  // free text
  RigidBodySpec body;
  Support support = Support::FixedPoint;
  Vec3 gravity_W = Vec3(0, 0, -9.81);  // m/s^2, space frame
  Mat3 R0_WB = Mat3::Identity();       // initial orientation, an exact rotation after loading
  Vec3 omega0_B = Vec3::Zero();        // rad/s, initial angular velocity in body components
  TimeGrid time;
  std::string output_times_at;  // "FILE:LINE:COL" of output.times in the scene file, for messages ("" if none)
  OutputSettings output;  // what is recorded, in which format
  Formulation formulation;
  SolverSettings solver;
  ReferenceKind reference = ReferenceKind::Auto;  // for compare and study
  // Schema-2 scenes: the bodies, joints and forces (body, support, gravity_W,
  // R0_WB and omega0_B above are then unused). Unset for one-body scenes.
  std::optional<MultibodySpec> multibody;
};

// The Baumgarte gains a run uses, (a, b) in 1/s. Unset ones default to the
// initial angular speed |omega_0| (at least 1/s): drift is corrected within
// about one revolution. On the heavy top (150 rad/s) gains of 1/s left 100x
// more drift, and 10^4/s made the system stiff (3x the steps).
inline std::pair<double, double> baumgarte_gains(const Scene& s) {
  const double rate = std::max(1.0, s.omega0_B.norm());
  return {s.formulation.baumgarte.a.value_or(rate), s.formulation.baumgarte.b.value_or(rate)};
}

// The drift at which the projection scheme projects. Unset: 100 atol. A
// threshold near atol restarts IDA almost every step, since each step's own
// error is about atol (on the heavy top: 1.5 million restarts in 2 s).
inline double projection_threshold(const Scene& s) {
  return s.formulation.projection.threshold.value_or(100.0 * s.solver.atol);
}

}  // namespace rigidae
