#pragma once
// IDA's Newton convergence test, with one change: the convergence rate a
// step's first correction is judged by is never taken below kCarriedRateFloor.
//
// IDA (6.4, ida_nls.c) accepts the corrector after its first iteration when
//   ss * ||delta_0|| <= epsNewt,   ss = rate / (1 - rate),
// where `rate` is the last one measured: ss is reset to 20 when the iteration
// matrix is rebuilt and to 100 when cj differs from the last accepted step's,
// and otherwise carried from step to step. A Newton iteration on a system
// that is nearly linear in the new unknowns measures rates of 1e-10 and less,
// so at a constant step size and order ss becomes so small that the next
// step's first correction is accepted whatever its size. For the states
// that is harmless (the local error test judges them); the multipliers are
// left out of that test (every scheme suppresses it: record/error_control.hpp),
// and nothing else checks them. Measured on the driven crank of
// crank_slider_driven alone (quaternion/lagrange/index1, rtol 1e-10): from
// t = 0.3 s on, steps were accepted whose residual left up to 81 N m in the
// crank's momentum rows, the crank's multipliers 2.5e8 of their absolute
// tolerance from the KKT solution at the same state, and the driving torque
// read up to 4e3 N m (the closed form: 0.245 N m at most); on the whole
// crank-slider up to 2.2e12 N m (0.925).
//
// Below the floor, the part of a first correction that falls on the unknowns
// outside the error test (its weighted norm, over all n) must be within
// epsNewt / ss_floor (about 30 x epsNewt) to be accepted; a larger one gets a
// second iteration, whose rate is measured. Elsewhere the test is IDA's, bit
// for bit (its bookkeeping of ss is rebuilt from IDA's public counters: steps,
// setups of the linear solver, the current cj; with the floor at 0 every
// guard pin of tests/guard/ was reproduced exactly). What it cost and earned
// on the corpus and the long runs: docs/benchmarks.md, "IDA's Newton: the
// multipliers' first corrections".
#include <nvector/nvector_serial.h>
#include <sundials/sundials_nonlinearsolver.h>

namespace rigidae::sun {

// The rate below which a carried rate is not trusted for a first correction.
inline constexpr double kCarriedRateFloor = 0.01;

struct IdaNewtonTest {
  void* ida_mem = nullptr;
  double ss = 20.0;          // IDA's ida_ss
  double oldnrm = 0.0;       // the first correction's norm in this attempt
  double cj_last = 0.0;      // cj of the last accepted step (IDA's ida_cjlast)
  double cj_seen = 0.0;      // cj at the last test
  long steps_seen = 0;       // IDA's step count at the last test
  long setups_seen = -1;     // its linear-solver setups at the last test
  N_Vector unchecked = nullptr;  // 1 on the unknowns IDA's error test leaves out, else 0 (null: none)
};

// A Newton solver for IDA with the test above; the caller frees it after
// IDAFree (IDA does not own a solver attached this way). Null on failure.
// unchecked: the mask of the unknowns outside the local error test (the
// algebraic ones when IDASetSuppressAlg is on), kept by the caller; null when
// the error test sees every unknown, and the test is then IDA's.
SUNNonlinearSolver attach_newton(void* ida_mem, N_Vector y, SUNContext ctx, N_Vector unchecked,
                                 IdaNewtonTest& test);

}  // namespace rigidae::sun
