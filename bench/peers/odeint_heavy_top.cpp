// Peer: Boost.Odeint, controlled Runge-Kutta-Fehlberg 7(8) on the 7-state
// quaternion ODE of the heavy top, the free body or the Lagrange top
// (--scene; body form):
//   q' = 1/2 q (x) (0, w),   J w' = -w x (J w) + c x (m R^T g),
// J the inertia about the pivot, c the COM in body axes, g in space axes.
// One JSON line per tolerance (abs = rel); wall time covers one whole
// integration from t = 0 to 2 s (the median of --repeats runs).
#include <boost/numeric/odeint.hpp>

#include "peer_common.hpp"

namespace odeint = boost::numeric::odeint;
using State = std::array<double, 7>;  // q (w, x, y, z), then w (body)

struct HeavyTop {
  long long* evals;  // counts right-hand-side evaluations
  void operator()(const State& s, State& ds, double /*t*/) const {
    ++*evals;
    const double qw = s[0], qx = s[1], qy = s[2], qz = s[3];
    const double wx = s[4], wy = s[5], wz = s[6];
    // q' = 1/2 q (x) (0, w)
    ds[0] = 0.5 * (-qx * wx - qy * wy - qz * wz);
    ds[1] = 0.5 * (qw * wx + qy * wz - qz * wy);
    ds[2] = 0.5 * (qw * wy + qz * wx - qx * wz);
    ds[3] = 0.5 * (qw * wz + qx * wy - qy * wx);
    // Gravity in body axes: R^T g, R the rotation of q / |q|. Space gravity is
    // (0, 0, gz), so R^T g = gz * (third row of R).
    const double n2 = qw * qw + qx * qx + qy * qy + qz * qz;
    const double gz = peers::scene.gravity[2];
    const double gb[3] = {gz * 2.0 * (qx * qz - qw * qy) / n2, gz * 2.0 * (qy * qz + qw * qx) / n2,
                          gz * (qw * qw - qx * qx - qy * qy + qz * qz) / n2};
    const double F[3] = {peers::scene.mass * gb[0], peers::scene.mass * gb[1], peers::scene.mass * gb[2]};
    const double* c = peers::scene.com;
    const double* J = peers::scene.Jpivot;
    const double L[3] = {J[0] * wx, J[1] * wy, J[2] * wz};
    const double tau[3] = {c[1] * F[2] - c[2] * F[1], c[2] * F[0] - c[0] * F[2], c[0] * F[1] - c[1] * F[0]};
    ds[4] = (-(wy * L[2] - wz * L[1]) + tau[0]) / J[0];
    ds[5] = (-(wz * L[0] - wx * L[2]) + tau[1]) / J[1];
    ds[6] = (-(wx * L[1] - wy * L[0]) + tau[2]) / J[2];
  }
};

int main(int argc, char** argv) try {
  const char* usage =
      "odeint_heavy_top [--scene heavy_top|free_body|lagrange_top] [--repeats N] [--budget S] [--settings tol,tol,...] [--reference FILE]\n"
      "  Boost.Odeint controlled runge_kutta_fehlberg78, abs = rel = tol (default 1e-3..1e-13)";
  auto opt = peers::parse_options(argc, argv, usage);
  if (opt.settings.empty())
    for (int e = 3; e <= 13; ++e) opt.settings.push_back(std::pow(10.0, -e));
  const auto q_ref = peers::load_reference(opt.reference);

  for (double tol : opt.settings) {
    State x{};
    long long evals = 0;
    std::size_t steps = 0;
    auto run = [&] {
      const double* q0 = peers::scene.q0;
      x = {q0[0], q0[1], q0[2], q0[3], peers::scene.w0[0], peers::scene.w0[1], peers::scene.w0[2]};
      evals = 0;
      auto stepper = odeint::make_controlled(tol, tol, odeint::runge_kutta_fehlberg78<State>());
      steps = odeint::integrate_adaptive(stepper, HeavyTop{&evals}, x, 0.0, peers::scene.t_end, 1e-4);
    };
    const auto [wall, n] = peers::median_wall(run, opt.repeats, opt.budget_s);
    peers::Row row;
    row.peer = "odeint";
    row.method = "rkf78";
    row.setting_kind = "tol";
    row.setting = tol;
    row.wall_s = wall;
    row.repeats = n;
    row.steps = static_cast<long long>(steps);
    row.rhs_evals = evals;
    row.q_final = peers::normalized({x[0], x[1], x[2], x[3]});
    if (q_ref) row.error_rad = peers::angle_between(*q_ref, row.q_final);
    peers::print_row(row);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "odeint_heavy_top: %s\n", e.what());
  return 1;
}
