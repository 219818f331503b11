// The IDA limit: the heavy top as a bare, hand-written IDA loop. No scene
// file, no recording, no virtual interfaces, no Eigen in the DAE: rigidae's
// quaternion/euler equations written out for this one body, with the IDA
// settings rigidae uses (the same tolerances by group, first step, maximum
// order, error-test suppression, dense linear solver, Jacobian kind). The
// wall-time ratio rigidae / this loop is the price of rigidae's generality.
//
//   bare_ida_heavy_top [--scheme index1|ggl] [--jacobian central|ida_dq|exact]
//                      [--rtols a,b,...] [--repeats N] [--budget S] [--reference FILE]
//                      [--check-jacobian]
//
// Unknowns: q = (w, x, y, z) (scalar first, body to space), omega (body), and
// for ggl the kinematic multiplier mu. Residual (J about the pivot, c the
// centre of mass from the pivot, body axes; g in space axes):
//   q' - 1/2 L(q) omega (+ 2 q mu)                 4 rows
//   J omega' - c x (m R(q)^T g) + omega x J omega   3 rows
//   |q|^2 - 1                                       1 row (ggl only)
// with R(q) the homogeneous quadratic rotation matrix (|q|^2 times a rotation),
// as in rigidae. One JSON line per rtol (atol = rtol) in the format of
// bench/peers/results.jsonl (peer "bare_ida"); wall time: median of N runs
// (fewer once they took S seconds), covering the consistent start, the first
// step estimate, IDA's creation and the whole integration from 0 to 2 s.
#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "machine_info.hpp"

namespace {

// The heavy top of problems/heavy_top.toml (SI).
constexpr double kMass = 15.0;
constexpr double kC[3] = {0.0, 1.0, 0.0};                        // pivot -> centre of mass, body
constexpr double kJ[3] = {0.234375 + 15.0, 0.46875, 0.234375 + 15.0};  // principal, about the pivot
constexpr double kGz = -9.81;                                    // gravity (0, 0, gz), space
constexpr double kOmega0[3] = {0.0, 150.0, -4.61538};
constexpr double kTEnd = 2.0;

struct Problem {
  bool ggl = false;
  int n = 7;
  long jac_residual_evals = 0;  // spent on central-difference Jacobians
};

// F(t, y, y'). Scalar code, written for this body. Not inlined, so that
// callgrind can count it (a call costs a few instructions).
__attribute__((noinline)) void residual(const Problem& p, const double* y, const double* yp, double* F) {
  const double qw = y[0], qx = y[1], qy = y[2], qz = y[3];
  const double wx = y[4], wy = y[5], wz = y[6];
  // 1/2 L(q) omega = 1/2 q (x) (0, omega)
  F[0] = yp[0] + 0.5 * (qx * wx + qy * wy + qz * wz);
  F[1] = yp[1] - 0.5 * (qw * wx + qy * wz - qz * wy);
  F[2] = yp[2] - 0.5 * (qw * wy + qz * wx - qx * wz);
  F[3] = yp[3] - 0.5 * (qw * wz + qx * wy - qy * wx);
  if (p.ggl) {
    const double mu2 = 2.0 * y[7];
    F[0] += mu2 * qw, F[1] += mu2 * qx, F[2] += mu2 * qy, F[3] += mu2 * qz;
    F[7] = qw * qw + qx * qx + qy * qy + qz * qz - 1.0;
  }
  // m R^T g: gz times the third row of R(q).
  const double b0 = kMass * kGz * 2.0 * (qx * qz - qw * qy);
  const double b1 = kMass * kGz * 2.0 * (qy * qz + qw * qx);
  const double b2 = kMass * kGz * (qw * qw - qx * qx - qy * qy + qz * qz);
  const double tau0 = kC[1] * b2 - kC[2] * b1, tau1 = kC[2] * b0 - kC[0] * b2, tau2 = kC[0] * b1 - kC[1] * b0;
  const double L0 = kJ[0] * wx, L1 = kJ[1] * wy, L2 = kJ[2] * wz;
  F[4] = kJ[0] * yp[4] - tau0 + (wy * L2 - wz * L1);
  F[5] = kJ[1] * yp[5] - tau1 + (wz * L0 - wx * L2);
  F[6] = kJ[2] * yp[6] - tau2 + (wx * L1 - wy * L0);
}

int res_fn(realtype, N_Vector yy, N_Vector yp, N_Vector rr, void* data) {
  residual(*static_cast<Problem*>(data), N_VGetArrayPointer(yy), N_VGetArrayPointer(yp), N_VGetArrayPointer(rr));
  return 0;
}

// dF/dy by central differences and dF/dy' by one large forward difference
// (F is affine in y'): the same algorithm and steps as rigidae's "central".
void central_jacobian(Problem& p, double cj, const double* y, const double* yp, double* J) {
  const int n = p.n;
  double yv[8], ypv[8], Fb[8], Fp[8], Fm[8];
  std::memcpy(yv, y, n * sizeof(double));
  std::memcpy(ypv, yp, n * sizeof(double));
  residual(p, y, yp, Fb);
  p.jac_residual_evals += 3 * n + 1;
  for (int j = 0; j < n; ++j) {
    const double dy = 6.0e-6 * std::max(1.0, std::abs(y[j]));
    yv[j] = y[j] + dy;
    residual(p, yv, yp, Fp);
    yv[j] = y[j] - dy;
    residual(p, yv, yp, Fm);
    yv[j] = y[j];
    for (int i = 0; i < n; ++i) J[j * n + i] = (Fp[i] - Fm[i]) / (2.0 * dy);
    const double dyp = std::max(1.0, std::abs(yp[j]));
    ypv[j] = yp[j] + dyp;
    residual(p, y, ypv, Fp);
    ypv[j] = yp[j];
    for (int i = 0; i < n; ++i) J[j * n + i] += cj * (Fp[i] - Fb[i]) / dyp;
  }
}

// dF/dy + cj dF/dy' in closed form.
void exact_jacobian(const Problem& p, double cj, const double* y, double* J) {
  const int n = p.n;
  std::fill(J, J + n * n, 0.0);
  auto at = [&](int i, int j) -> double& { return J[j * n + i]; };
  const double qw = y[0], qx = y[1], qy = y[2], qz = y[3];
  const double wx = y[4], wy = y[5], wz = y[6];
  // Kinematic rows: d(-1/2 L(q) omega)/dq = -1/2 W(omega), W linear in omega.
  const double W[4][4] = {{0, -wx, -wy, -wz}, {wx, 0, wz, -wy}, {wy, -wz, 0, wx}, {wz, wy, -wx, 0}};
  const double L[4][3] = {{-qx, -qy, -qz}, {qw, -qz, qy}, {qz, qw, -qx}, {-qy, qx, qw}};
  const double q[4] = {qw, qx, qy, qz};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) at(i, j) = -0.5 * W[i][j];
    for (int j = 0; j < 3; ++j) at(i, 4 + j) = -0.5 * L[i][j];
    at(i, i) += cj;
    if (p.ggl) {
      at(i, i) += 2.0 * y[7];
      at(i, 7) = 2.0 * q[i];
      at(7, i) = 2.0 * q[i];
    }
  }
  // Dynamic rows: d(-tau)/dq with tau = m c x b(q), b = R(q)^T g.
  const double s = kMass * kGz * 2.0;
  const double db[3][4] = {{-s * qy, s * qz, -s * qw, s * qx},
                           {s * qx, s * qw, s * qz, s * qy},
                           {s * qw, -s * qx, -s * qy, s * qz}};
  for (int j = 0; j < 4; ++j) {
    at(4, j) = -(kC[1] * db[2][j] - kC[2] * db[1][j]);
    at(5, j) = -(kC[2] * db[0][j] - kC[0] * db[2][j]);
    at(6, j) = -(kC[0] * db[1][j] - kC[1] * db[0][j]);
  }
  // d(omega x J omega)/d omega = hat(omega) J - hat(J omega).
  const double Lw[3] = {kJ[0] * wx, kJ[1] * wy, kJ[2] * wz};
  const double hw[3][3] = {{0, -wz, wy}, {wz, 0, -wx}, {-wy, wx, 0}};
  const double hL[3][3] = {{0, -Lw[2], Lw[1]}, {Lw[2], 0, -Lw[0]}, {-Lw[1], Lw[0], 0}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) at(4 + i, 4 + j) = hw[i][j] * kJ[j] - hL[i][j] + (i == j ? cj * kJ[i] : 0.0);
}

int central_jac_fn(realtype, realtype cj, N_Vector yy, N_Vector yp, N_Vector, SUNMatrix J, void* data, N_Vector,
                   N_Vector, N_Vector) {
  central_jacobian(*static_cast<Problem*>(data), cj, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp),
                   SUNDenseMatrix_Data(J));
  return 0;
}

int exact_jac_fn(realtype, realtype cj, N_Vector yy, N_Vector, N_Vector, SUNMatrix J, void* data, N_Vector, N_Vector,
                 N_Vector) {
  exact_jacobian(*static_cast<Problem*>(data), cj, N_VGetArrayPointer(yy), SUNDenseMatrix_Data(J));
  return 0;
}

// y' consistent with y (and mu from d/dt |q|^2 = 0 for ggl), as rigidae's
// consistent_start does.
void consistent_yp(const Problem& p, double* y, double* yp) {
  std::fill(yp, yp + p.n, 0.0);
  double F[8];
  residual(p, y, yp, F);  // with y' = 0 (and the current mu): F = -(rates)
  if (p.ggl) {
    // mu = (Phi_q qdot) / (Phi_q Phi_q^T) with qdot = 1/2 L omega
    double qq = 0.0, qqd = 0.0;
    const double mu_old = y[7];
    for (int i = 0; i < 4; ++i) {
      const double qdot = -(F[i] - 2.0 * mu_old * y[i]);
      qq += y[i] * y[i];
      qqd += y[i] * qdot;
    }
    y[7] = 2.0 * qqd / (4.0 * qq);
    residual(p, y, yp, F);
  }
  for (int i = 0; i < 4; ++i) yp[i] = -F[i];
  for (int i = 0; i < 3; ++i) yp[4 + i] = -F[4 + i] / kJ[i];
}

struct Result {
  double wall_s = 0.0;
  long steps = 0, nre = 0, nre_ls = 0, nje = 0, nni = 0, netf = 0, nncf = 0;
  double q[4] = {0, 0, 0, 0};
  bool ok = false;
  std::string message;
};

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string(what) + " failed: " + IDAGetReturnFlagName(flag));
}

// Not inlined, so that callgrind can count it.
__attribute__((noinline)) Result solve(bool ggl, const std::string& jac, double rtol) {
  Result r;
  const auto t0 = std::chrono::steady_clock::now();
  Problem p;
  p.ggl = ggl;
  p.n = ggl ? 8 : 7;
  const int n = p.n;

  double y[8] = {1, 0, 0, 0, kOmega0[0], kOmega0[1], kOmega0[2], 0}, yp[8];
  consistent_yp(p, y, yp);

  // First step: order-1 local error h^2/2 |y''| equal to the tolerance, y''
  // from consistent y' along a short explicit step (rigidae's estimate).
  double h0;
  {
    const int nd = 7;
    double rate = 0.0;
    for (int i = 0; i < nd; ++i) rate = std::max(rate, std::abs(yp[i]));
    const double delta = std::min(1e-4 * kTEnd, 1e-3 / rate);
    double y1[8], yp1[8];
    for (int i = 0; i < n; ++i) y1[i] = y[i] + delta * yp[i];
    consistent_yp(p, y1, yp1);
    double sum = 0.0;
    for (int i = 0; i < nd; ++i) {
      const double w = rtol * std::abs(y[i]) + rtol;
      const double d = (yp1[i] - yp[i]) / delta / w;
      sum += d * d;
    }
    const double norm = std::sqrt(sum / nd);
    h0 = std::min(norm > 0 ? std::sqrt(2.0 / norm) : 1e-3 * kTEnd, 1e-3 * kTEnd);
  }

  SUNContext ctx = nullptr;
  if (SUNContext_Create(nullptr, &ctx) != 0) throw std::runtime_error("SUNContext_Create failed");
  N_Vector yy = N_VNew_Serial(n, ctx), yyp = N_VNew_Serial(n, ctx), id = N_VNew_Serial(n, ctx),
           atol = N_VNew_Serial(n, ctx);
  SUNMatrix A = SUNDenseMatrix(n, n, ctx);
  SUNLinearSolver LS = SUNLinSol_Dense(yy, A, ctx);
  void* mem = IDACreate(ctx);
  std::copy(y, y + n, N_VGetArrayPointer(yy));
  std::copy(yp, yp + n, N_VGetArrayPointer(yyp));
  double* idv = N_VGetArrayPointer(id);
  double* av = N_VGetArrayPointer(atol);
  for (int i = 0; i < 7; ++i) idv[i] = 1.0, av[i] = rtol;
  if (ggl) idv[7] = 0.0, av[7] = std::max(rtol, std::pow(rtol, 0.75)) * std::max(1.0, std::abs(y[7]));

  check(IDAInit(mem, res_fn, 0.0, yy, yyp), "IDAInit");
  check(IDASVtolerances(mem, rtol, atol), "IDASVtolerances");
  check(IDASetUserData(mem, &p), "IDASetUserData");
  check(IDASetId(mem, id), "IDASetId");
  check(IDASetSuppressAlg(mem, SUNTRUE), "IDASetSuppressAlg");
  check(IDASetLinearSolver(mem, LS, A), "IDASetLinearSolver");
  if (jac == "central") check(IDASetJacFn(mem, central_jac_fn), "IDASetJacFn");
  if (jac == "exact") check(IDASetJacFn(mem, exact_jac_fn), "IDASetJacFn");
  check(IDASetMaxOrd(mem, 5), "IDASetMaxOrd");
  check(IDASetStopTime(mem, kTEnd), "IDASetStopTime");
  check(IDASetInitStep(mem, h0), "IDASetInitStep");

  double t = 0.0;
  r.ok = true;
  while (t < kTEnd) {
    const int flag = IDASolve(mem, kTEnd, &t, yy, yyp, IDA_ONE_STEP);
    if (flag < 0) {
      r.ok = false;
      r.message = IDAGetReturnFlagName(flag);
      break;
    }
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  IDAGetNumSteps(mem, &r.steps);
  IDAGetNumResEvals(mem, &r.nre);
  IDAGetNumLinResEvals(mem, &r.nre_ls);
  IDAGetNumJacEvals(mem, &r.nje);
  IDAGetNumNonlinSolvIters(mem, &r.nni);
  IDAGetNumErrTestFails(mem, &r.netf);
  IDAGetNumNonlinSolvConvFails(mem, &r.nncf);
  r.nre_ls += p.jac_residual_evals;
  std::copy(N_VGetArrayPointer(yy), N_VGetArrayPointer(yy) + 4, r.q);
  IDAFree(&mem);
  SUNLinSolFree(LS);
  SUNMatDestroy(A);
  for (N_Vector v : {yy, yyp, id, atol}) N_VDestroy(v);
  SUNContext_Free(&ctx);
  return r;
}

// The closed-form Jacobian against the central differences at a generic state.
double jacobian_check(bool ggl) {
  Problem p;
  p.ggl = ggl;
  p.n = ggl ? 8 : 7;
  double y[8] = {0.8, -0.3, 0.4, 0.33, 1.5, 150.0, -4.6, ggl ? 1e-3 : 0.0}, yp[8];
  consistent_yp(p, y, yp);
  y[7] = ggl ? 1e-3 : 0.0;
  double Je[64], Jc[64];
  const double cj = 1234.5;
  exact_jacobian(p, cj, y, Je);
  central_jacobian(p, cj, y, yp, Jc);
  double worst = 0.0;
  for (int k = 0; k < p.n * p.n; ++k) worst = std::max(worst, std::abs(Je[k] - Jc[k]) / std::max(1.0, std::abs(Jc[k])));
  return worst;
}

}  // namespace

int main(int argc, char** argv) try {
  std::string scheme = "index1", jac = "central";
  std::string ref_path = "bench/peers/heavy_top_reference.json";
  std::vector<double> rtols;
  int repeats = 3;
  double budget = 3.0;
  bool check_only = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error("missing value after " + a);
      return argv[++i];
    };
    if (a == "--scheme") scheme = next();
    else if (a == "--jacobian") jac = next();
    else if (a == "--rtols" || a == "--rtol") {
      std::stringstream ss(next());
      std::string s;
      while (std::getline(ss, s, ',')) rtols.push_back(std::stod(s));
    } else if (a == "--repeats") repeats = std::max(1, std::stoi(next()));
    else if (a == "--budget") budget = std::stod(next());
    else if (a == "--reference") ref_path = next();
    else if (a == "--check-jacobian") check_only = true;
    else throw std::runtime_error("unknown option " + a + " (see the header of bare_ida_heavy_top.cpp)");
  }
  if (scheme != "index1" && scheme != "ggl") throw std::runtime_error("--scheme index1|ggl");
  if (jac != "central" && jac != "ida_dq" && jac != "exact") throw std::runtime_error("--jacobian central|ida_dq|exact");
  const bool ggl = scheme == "ggl";
  if (check_only) {
    const double worst = jacobian_check(ggl);
    std::printf("{\"jacobian_check\": \"%s\", \"max_rel_diff_exact_vs_central\": %.3e}\n", scheme.c_str(), worst);
    return worst < 1e-6 ? 0 : 1;
  }
  if (rtols.empty())
    for (int e = 3; e <= 13; ++e) rtols.push_back(std::pow(10.0, -e));

  std::ifstream in(ref_path);
  if (!in) throw std::runtime_error(ref_path + ": cannot open the reference (--reference FILE)");
  const nlohmann::json ref = nlohmann::json::parse(in);
  const auto qr = ref.at("quaternion").get<std::vector<double>>();
  const Eigen::Vector4d q_ref(qr[0], qr[1], qr[2], qr[3]);

  nlohmann::json info = bench::machine_info("bare_ida_heavy_top");
  std::cout << info.dump() << std::endl;
  for (double rtol : rtols) {
    std::vector<double> walls;
    Result first;
    double total = 0.0;
    for (int k = 0; k < repeats; ++k) {
      Result r = solve(ggl, jac, rtol);
      if (k == 0) first = r;
      walls.push_back(r.wall_s);
      total += r.wall_s;
      if (total >= budget || !r.ok) break;
    }
    const Eigen::Vector4d q(first.q[0], first.q[1], first.q[2], first.q[3]);
    nlohmann::json row = {{"peer", "bare_ida"},
                          {"scene", "heavy_top"},
                          {"method", "quaternion/euler/" + scheme},
                          {"jacobian", jac},
                          {"setting", rtol},
                          {"setting_kind", "rtol"},
                          {"wall_s", bench::median(walls)},
                          {"repeats", walls.size()},
                          {"status", first.ok ? "success" : "failed"},
                          {"steps", first.steps},
                          {"residual_evals", first.nre},
                          {"jacobian_residual_evals", first.nre_ls},
                          {"rhs_evals", first.nre + first.nre_ls},
                          {"jacobian_evals", first.nje},
                          {"nonlinear_iters", first.nni},
                          {"error_test_fails", first.netf},
                          {"nonlinear_conv_fails", first.nncf}};
    if (first.ok) row["error_rad"] = bench::angle_between(q_ref, q);
    else row["error_rad"] = nullptr, row["message"] = first.message;
    const double nq = q.norm();
    row["q_final"] = {q[0] / nq, q[1] / nq, q[2] / nq, q[3] / nq};
    std::cout << row.dump() << std::endl;
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bare_ida_heavy_top: %s\n", e.what());
  return 1;
}
