// An explicit embedded Runge-Kutta pair that rigidae gives ARKODE (ERKStep
// accepts user tables; ARKODE 6.4's own list is integrators.cpp's names).
#pragma once

#include <vector>

namespace rigidae::ode {

struct ButcherTable {
  int stages = 0;
  int order = 0;           // of the propagated solution (weights b)
  int embedded_order = 0;  // of the solution the error is estimated against (weights d)
  std::vector<double> a;   // stages x stages, row-major, strictly lower triangular
  std::vector<double> b, d, c;
};

// Prince and Dormand's RK8(7)13M (prince_dormand_87.cpp).
const ButcherTable& prince_dormand_87();

}  // namespace rigidae::ode
