#pragma once
// A constraint row as plain data: a constant plus a sum of (at most three)
// terms c (alpha . beta), alpha and beta vectors fixed in a body (or in space,
// for the ground). alpha and beta may be the same vector (a squared length).
//
// A body vector is a point p = x + R s or a direction d = R s, s fixed in the
// body (from its centre of mass); for the ground (kGround) s is constant in
// space. Joint types (model/joint_type.hpp) state their rows in these terms;
// the multibody assembler evaluates them and their exact derivatives
// (multibody/constraint_rows.hpp). Each row also says what its multiplier is
// physically (`RowReaction`), which is how a joint's reaction is reported:
//   Point      p_a . e_k - p_b . e_k (coincident points, e_k fixed in space):
//              lambda is the force component along e_k on body b (N)
//   Line       p_b . n - p_a . n, n fixed in a (point on a line):
//              the force -lambda n on body b (N)
//   Turn       d_a . d_b (perpendicular directions):
//              the torque lambda (d_a x d_b) on body b (N m)
//   Distance   ((p_b - p_a) . (p_b - p_a) - L^2) / (2 L) (a rod of length L):
//              the force -lambda (p_b - p_a) / L on body b (N): lambda is
//              the rod's tension (three terms and the constant -L/2)
//   Coordinate a joint coordinate's cosine, sine or displacement row (not a
//              constraint: read by joint coordinates and torsion springs)
#include <string>

#include "rigidae/core/types.hpp"

namespace rigidae {

// Index of the ground in joint and force body references.
inline constexpr int kGround = -1;

// A vector fixed in a body (or in space, for the ground).
struct BodyVector {
  int body = kGround;
  Vec3 s = Vec3::Zero();
  bool point = false;  // p = x + R s, else d = R s
};

struct DotTerm {
  double coeff = 1.0;
  BodyVector a, b;
};

enum class RowReaction { Point, Line, Turn, Distance, Coordinate };

struct ConstraintRow {
  std::string name;  // e.g. "x", "axis_n1": names the multiplier's columns
  DotTerm terms[3];
  int n_terms = 1;
  double constant = 0.0;  // added to the terms' sum
  RowReaction reaction = RowReaction::Coordinate;
};

}  // namespace rigidae
