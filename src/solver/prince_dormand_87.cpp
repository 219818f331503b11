// Prince and Dormand's 13-stage embedded pair RK8(7)13M, as published
// (P. J. Prince, J. R. Dormand, "High order embedded Runge-Kutta formulae",
// J. Comput. Appl. Math. 7 (1981) 67-75; Hairer, Norsett, Wanner, Solving
// ODEs I, II.5): rational approximations good to about 1e-18, the
// 8th-order weights b propagated, the 7th-order weights d estimating the
// error; c_i = sum_j a_ij. tests/unit/test_butcher_tables.cpp checks every
// order condition (200 rooted trees up to order 8) against them.
//
// Why this pair: Fehlberg's 7(8), the eighth-order table ARKODE 6.4 ships,
// estimates its error from four stages only, (41/840) h (k1 + k11 - k12 -
// k13), which vanishes for a quadrature y' = f(t) and is far too small on
// motions that are nearly one (measured: problems/singular_linkage.toml in
// Euler angles, a crank turning at constant rate, index1 at rtol 1e-7 took 7
// steps per second and ended 2e-3 off the closed form; docs/benchmarks.md).
// Prince and Dormand's pair estimates from the whole 7th-order solution.
#include "butcher_table.hpp"

namespace rigidae::ode {

namespace {

ButcherTable build() {
  constexpr int s = 13;
  ButcherTable t;
  t.stages = s;
  t.order = 8;
  t.embedded_order = 7;
  t.a.assign(s * s, 0.0);
  t.c.assign(s, 0.0);
  auto a = [&](int i, int j, double v) { t.a[static_cast<std::size_t>(i * s + j)] = v; };
  a(1, 0, 1.0 / 18.0);
  a(2, 0, 1.0 / 48.0), a(2, 1, 1.0 / 16.0);
  a(3, 0, 1.0 / 32.0), a(3, 2, 3.0 / 32.0);
  a(4, 0, 5.0 / 16.0), a(4, 2, -75.0 / 64.0), a(4, 3, 75.0 / 64.0);
  a(5, 0, 3.0 / 80.0), a(5, 3, 3.0 / 16.0), a(5, 4, 3.0 / 20.0);
  a(6, 0, 29443841.0 / 614563906.0), a(6, 3, 77736538.0 / 692538347.0), a(6, 4, -28693883.0 / 1125000000.0),
      a(6, 5, 23124283.0 / 1800000000.0);
  a(7, 0, 16016141.0 / 946692911.0), a(7, 3, 61564180.0 / 158732637.0), a(7, 4, 22789713.0 / 633445777.0),
      a(7, 5, 545815736.0 / 2771057229.0), a(7, 6, -180193667.0 / 1043307555.0);
  a(8, 0, 39632708.0 / 573591083.0), a(8, 3, -433636366.0 / 683701615.0), a(8, 4, -421739975.0 / 2616292301.0),
      a(8, 5, 100302831.0 / 723423059.0), a(8, 6, 790204164.0 / 839813087.0), a(8, 7, 800635310.0 / 3783071287.0);
  a(9, 0, 246121993.0 / 1340847787.0), a(9, 3, -37695042795.0 / 15268766246.0),
      a(9, 4, -309121744.0 / 1061227803.0), a(9, 5, -12992083.0 / 490766935.0),
      a(9, 6, 6005943493.0 / 2108947869.0), a(9, 7, 393006217.0 / 1396673457.0), a(9, 8, 123872331.0 / 1001029789.0);
  a(10, 0, -1028468189.0 / 846180014.0), a(10, 3, 8478235783.0 / 508512852.0),
      a(10, 4, 1311729495.0 / 1432422823.0), a(10, 5, -10304129995.0 / 1701304382.0),
      a(10, 6, -48777925059.0 / 3047939560.0), a(10, 7, 15336726248.0 / 1032824649.0),
      a(10, 8, -45442868181.0 / 3398467696.0), a(10, 9, 3065993473.0 / 597172653.0);
  a(11, 0, 185892177.0 / 718116043.0), a(11, 3, -3185094517.0 / 667107341.0),
      a(11, 4, -477755414.0 / 1098053517.0), a(11, 5, -703635378.0 / 230739211.0),
      a(11, 6, 5731566787.0 / 1027545527.0), a(11, 7, 5232866602.0 / 850066563.0),
      a(11, 8, -4093664535.0 / 808688257.0), a(11, 9, 3962137247.0 / 1805957418.0),
      a(11, 10, 65686358.0 / 487910083.0);
  a(12, 0, 403863854.0 / 491063109.0), a(12, 3, -5068492393.0 / 434740067.0),
      a(12, 4, -411421997.0 / 543043805.0), a(12, 5, 652783627.0 / 914296604.0),
      a(12, 6, 11173962825.0 / 925320556.0), a(12, 7, -13158990841.0 / 6184727034.0),
      a(12, 8, 3936647629.0 / 1978049680.0), a(12, 9, -160528059.0 / 685178525.0),
      a(12, 10, 248638103.0 / 1413531060.0);
  t.b = {14005451.0 / 335480064.0,      0.0,
         0.0,                          0.0,
         0.0,                          -59238493.0 / 1068277825.0,
         181606767.0 / 758867731.0,    561292985.0 / 797845732.0,
         -1041891430.0 / 1371343529.0, 760417239.0 / 1151165299.0,
         118820643.0 / 751138087.0,    -528747749.0 / 2220607170.0,
         1.0 / 4.0};
  t.d = {13451932.0 / 455176623.0,     0.0,
         0.0,                          0.0,
         0.0,                          -808719846.0 / 976000145.0,
         1757004468.0 / 5645159321.0,  656045339.0 / 265891186.0,
         -3867574721.0 / 1518517206.0, 465885868.0 / 322736535.0,
         53011238.0 / 667516719.0,     2.0 / 45.0,
         0.0};
  for (int i = 0; i < s; ++i) {
    double sum = 0.0;
    for (int j = 0; j < i; ++j) sum += t.a[static_cast<std::size_t>(i * s + j)];
    t.c[static_cast<std::size_t>(i)] = sum;
  }
  return t;
}

}  // namespace

const ButcherTable& prince_dormand_87() {
  static const ButcherTable table = build();
  return table;
}

}  // namespace rigidae::ode
