#pragma once
// Assembled starts: the scene gives the poses and velocities of the bodies
// that drive the mechanism (held: kept as given) and guesses for the others;
// the start moves the others onto the joints.
//
// Unknowns: per body a displacement dx (m, space) and a small rotation dtheta
// (rad, space: R <- exp(hat(dtheta)) R); per row r of every joint its
// miss phi_r = sum_k c_k a_k . b_k over space vectors (x + R s for a point,
// R s for a direction) and its gradient
//   d(R s)/d(dx, dtheta) = [0, -hat(R s)],  d(x + R s)/d(dx, dtheta) = [I, -hat(R s)],
// so G (rows x 6 per body) is also the map from the space twists (v, omega)
// to phi' (velocity level). Rows with a point are divided by the length
// scale L (the largest joint-point offset from a centre of mass) so that all
// rows are dimensionless.
//
// Positions: Gauss-Newton steps of least change in the mass metric
// W = diag(m I, R J R^T) per body, the held bodies not moving (their block of
// W^-1 is zero):
//   dz = -W^-1 G^T (G W^-1 G^T + mu I)^-1 phi,   mu = 1e-12 max diag(G W^-1 G^T)
// (the small mu admits the dependent rows of redundant loops), halved while
// the largest |phi| does not fall. Velocities: the same least change from the
// given velocities onto G V = 0, where a held body keeps its angular velocity
// but its centre-of-mass velocity follows its joints (so a crank needs only
// its rate). A start that stays more than
// start_tolerance off a joint is refused at that joint's [[joints]] table.
//
// A body held at a pivot o (BodySpec::pivot_W) only turns: x = o + R c with
// the lever c = R_given^T (x_given - o) (or com_from_pivot_B), the body's
// geometry, kept. Its unknowns are dtheta alone: a point's gradient is
// [-, -hat(x + R s - o)] (no translation columns), its metric block the
// inertia about the pivot, J_o = J_c + m (|c|^2 I - c c^T), and its velocity
// after the solve v = omega x (x - o).
#include <string>
#include <vector>

#include "rigidae/model/multibody_spec.hpp"

namespace rigidae::multibody {

// How far the assembly moved one body from the scene's guess.
struct AssembledBody {
  int body = 0;
  double moved_m = 0.0;                 // |x - x_given|
  double turned_rad = 0.0;              // angle of R R_given^T
  double velocity_change = 0.0;         // |v - v_given|, m/s
  double angular_velocity_change = 0.0; // |omega - omega_given| (space), rad/s
};

struct AssemblyReport {
  bool done = false;            // the scene asked for an assembled start
  std::vector<int> held;        // bodies kept as given
  int iterations = 0;           // Gauss-Newton steps at the position level
  double initial_miss = 0.0;    // largest |phi| of the joints' rows at the guess (m or rad)
  double final_miss = 0.0;      // ... after the assembly
  double initial_velocity_miss = 0.0;  // largest |phi'| at the given velocities (m/s or rad/s)
  double final_velocity_miss = 0.0;
  std::vector<AssembledBody> bodies;  // every body (a held one moves only in its velocity)
  std::string note;             // one line for the printed report
};

// Moves spec's bodies (other than spec.assembly.held) onto the joints and
// their velocities onto the joints' velocity constraints; returns what it did.
// Throws InputError, positioned at the joint that still misses, when the
// mechanism cannot be assembled near the guesses.
AssemblyReport assemble_start(MultibodySpec& spec);

}  // namespace rigidae::multibody
