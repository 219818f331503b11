#pragma once
// Applied forces as elements behind one small interface: gravity, constant
// loads, point-to-point spring-dampers, torsional spring-dampers in joints.
// Each element type is one file under src/multibody/force_elements/ (its
// equations in the opening comment) with one line in that folder's
// registry.cpp; the assembler loops over the elements and never asks which
// type one is.
//
// Sign convention: the dynamic rows hold M v' - f, so an element with
// generalized force Q (the power Q . v) subtracts Q from them, and its
// iteration-matrix part is -dQ/dq (columns of q) and -dQ/dv (columns of v).
// One virtual call per element per residual or matrix evaluation; inside,
// fixed-size Eigen types on the stack: nothing is allocated.
#include <memory>
#include <vector>

#include "rigidae/model/multibody_spec.hpp"
#include "rigidae/multibody/body_vector.hpp"
#include "rigidae/multibody/jacobian_sink.hpp"

namespace rigidae::multibody {

// What an element reads of the system: each body's state at the current
// evaluation (its placement partials of the order the assembler asked for)
// and where its unknowns sit. Filled by the assembler.
struct ForceBodies {
  std::vector<const BodyState*> state;  // per body
  std::vector<double> mass;             // kg
  std::vector<int> q_group, v_group;    // unknown groups (JacobianSink)
  std::vector<int> v_offset;            // offset of the body's velocities in F
  Vec3 gravity_W = Vec3::Zero();        // m/s^2
  double t = 0.0;                       // s, the time of the evaluation (time-dependent loads)
  const BodyState* of(int body) const { return body == kGround ? nullptr : state[static_cast<std::size_t>(body)]; }
};

class ForceElement {
 public:
  virtual ~ForceElement() = default;
  // F[v rows] -= Q.
  virtual void add_force(const ForceBodies& b, double* F) = 0;
  // -dQ/dq and -dQ/dv into the iteration matrix (the pattern is recorded
  // from the first call: write every block that can be nonzero).
  virtual void add_jacobian(const ForceBodies& b, JacobianSink& sink) = 0;
  // The potential whose negative gradient is Q's conservative part (J).
  virtual double potential_energy(const ForceBodies& b) = 0;
  // Stored elastic energy (a spring's), as opposed to the potential of a
  // field (gravity, a constant force): the energy check scales by it.
  virtual bool elastic() const { return false; }
  // Q = -dV/dq exactly (no damping, no follower load): the energy check
  // applies only when every element is conservative.
  virtual bool conservative() const = 0;
  // The power Q . v at the bodies' evaluation (W): the energy check integrates
  // it for elements that are not conservative but whose work is known (a
  // time-dependent load). Elements that return no power leave the check off.
  virtual bool has_power() const { return false; }
  virtual double power(const ForceBodies&) { return 0.0; }
  // Elements with a state of their own besides y (a torsion angle's branch):
  // reset at the start, follow after each accepted step (bodies evaluated).
  virtual bool follows_motion() const { return false; }
  virtual void reset() {}
  virtual void follow(const ForceBodies&) {}
  // Whether add_force can write a pivoted body's rows (its rotation rows:
  // it has no others). Gravity cannot (a pivoted body's rotation block
  // carries the gravity torque about its pivot); an element that does not
  // say is taken to. MultibodyProblem::bodies_decoupled reads it.
  virtual bool acts_on_pivoted_bodies() const { return true; }
};

using ForceElements = std::vector<std::unique_ptr<ForceElement>>;

// Every element of a scene, registry order (registry.cpp), then scene order.
ForceElements make_force_elements(const MultibodySpec& spec);

}  // namespace rigidae::multibody
