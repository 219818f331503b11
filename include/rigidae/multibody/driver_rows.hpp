#pragma once
// A driver's rheonomic constraint row (issue 22 item 6): a joint coordinate
// prescribed as f(t) (model/time_function.hpp), from the coordinate's rows
// (model/joint_type.hpp: {C, S} for an angle, {d} for a length).
//
//   Length  Phi = d - f(t)
//   Angle   Phi = -sin f C + cos f S  (= r sin(theta - f), r^2 = C^2 + S^2)
//
// Written Phi = sum_k alpha_k(t) c_k(q) + beta(t) (alpha = (-sin f, cos f),
// beta = 0 for an angle; alpha = 1, beta = -f for a length), the levels that
// the assembler reads (constraint_rows.hpp's BlockEval, one row) are
//   Phi
//   Gv    = Phi' = sum alpha_k G_k v + sum alpha_k' c_k + beta'          (G v + Phi_t)
//   cacc  = Phi'' - G v'
//         = sum alpha_k cacc_k + 2 sum alpha_k' G_k v + sum alpha_k'' c_k + beta''
// with G = sum alpha_k G_k; and their exact derivatives
//   d(Gv)/dq   = sum alpha_k d(G_k v)/dq + sum alpha_k' c_k,q
//   d(cacc)/dq = sum alpha_k dcacc_k/dq + 2 sum alpha_k' d(G_k v)/dq + sum alpha_k'' c_k,q
//   d(cacc)/dv = sum alpha_k dcacc_k/dv + 2 sum alpha_k' G_k
//   d(G^T l)/dq, d(Phi_q^T m)/dq: the coordinate rows' with multipliers alpha_k l, alpha_k m.
// alpha' = f' (-cos f, -sin f), alpha'' = f'^2 (sin f, -cos f) + f'' (-cos f, -sin f).
// The time derivatives never enter the iteration matrix (it is d/dy, d/dy').
//
// The multiplier lambda acts on the bodies as -G^T lambda: the generalized
// force along the coordinate is -lambda dPhi/dtheta = -lambda (C cos f + S sin f)
// (= -lambda r at theta = f), the driving torque on b about the joint's
// axis in the coordinate's positive sense (its reaction on a); for a length
// -lambda, the driving force on b along the axis. Its power is the driving
// torque (force) times theta' (d'): the work a driver does.
#include "rigidae/model/joint_type.hpp"
#include "rigidae/model/time_function.hpp"
#include "rigidae/multibody/constraint_rows.hpp"

namespace rigidae::multibody {

struct DriverRow {
  const JointCoordinate* coordinate = nullptr;
  ConstraintRow rows[2];  // the coordinate's rows
  const TimeFunction* motion = nullptr;
  int row_count() const { return coordinate->row_count(); }
};

// Values of the driver's row at time t into out (nr = 1). `scratch` holds the
// coordinate rows' evaluation. Allocates nothing.
void evaluate_driver(const DriverRow& d, double t, const BlockSides& sides, BlockEval& scratch, BlockEval& out);
// Values and derivatives (differentiate_rows's outputs for the one row);
// lambda, mu: the row's multipliers (null when absent).
void differentiate_driver(const DriverRow& d, double t, const BlockSides& sides, const double* const a[2],
                          const double* lambda, const double* mu, BlockEval& scratch, BlockEval& out);
// The generalized force along the coordinate for multiplier lambda (the
// driving torque, N m, or force, N), after evaluate_driver (scratch filled):
// -lambda for a length, -lambda r for an angle with r = |(C, S)| (r cos(theta
// - f) exactly: the two differ by the square of the constraint's drift, and
// r needs no time, so any state's row can report it).
double driving_effort(const DriverRow& d, const BlockEval& scratch, double lambda);

// How far the coordinate is from the prescribed f(t), after evaluate_driver
// (scratch filled): d - f (m) for a length; for an angle theta - f wrapped
// to [-pi, pi] (rad), atan2(r sin(theta - f), r cos(theta - f)), not the row
// r sin(theta - f), which also vanishes half a turn off (where the driving
// torque -lambda dPhi/dtheta would come out with the wrong sign).
double prescribed_miss(const DriverRow& d, const BlockEval& scratch, double t);
// The angle theta = atan2(S, C) in (-pi, pi] that the coordinate's rows read
// (angles only; after evaluate_driver).
double coordinate_angle(const BlockEval& scratch);

}  // namespace rigidae::multibody
