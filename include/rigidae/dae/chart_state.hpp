#pragma once
// The chart a run's state is written in now (Euler angles: the sequence),
// for those who read the state as it goes (the recorder): the DAE problem
// (single_body_problem.hpp) and the ODE form (single_body_ode.hpp) each keep
// it as their own state besides y.
#include "rigidae/dae/dae_system.hpp"

namespace rigidae {

class ChartState {
 public:
  virtual ~ChartState() = default;
  virtual const DaeSystem& system() const = 0;
  virtual int chart() const = 0;
  // The representation in the current chart.
  const Representation& representation() const { return system().representation(chart()); }
};

}  // namespace rigidae
