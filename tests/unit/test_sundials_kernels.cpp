// rigidae's serial vector and dense LU against SUNDIALS' own (NVECTOR_SERIAL
// with its fused operations off, as the integrators ran before, and
// SUNLinSol_Dense): every result must be bit-identical, on random data of
// every size from 1 to 20 and with the coefficients that select N_VLinearSum's
// special cases; the solve must also solve (residual at round-off), and a
// singular matrix must fail in both the same way.
#include <doctest/doctest.h>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "solver/dense_lu_solver.hpp"
#include "solver/serial_vector.hpp"

TEST_SUITE_BEGIN("unit");

namespace {

struct Context {
  SUNContext ctx = nullptr;
  Context() { SUNContext_Create(nullptr, &ctx); }
  ~Context() { SUNContext_Free(&ctx); }
};

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_bits(N_Vector a, N_Vector b) {
  const sunindextype n = N_VGetLength(a);
  if (N_VGetLength(b) != n) return false;
  for (sunindextype i = 0; i < n; ++i)
    if (!same_bits(N_VGetArrayPointer(a)[i], N_VGetArrayPointer(b)[i])) return false;
  return true;
}

// A pair of vectors with the same entries: SUNDIALS' (ref) and rigidae's (ours).
struct Pair {
  N_Vector ref, ours;
  Pair(sunindextype n, SUNContext ctx, std::mt19937& rng, double lo = -3.0, double hi = 3.0)
      : ref(N_VNew_Serial(n, ctx)), ours(rigidae::sun::new_serial_vector(n, ctx)) {
    std::uniform_real_distribution<double> u(lo, hi);
    for (sunindextype i = 0; i < n; ++i) N_VGetArrayPointer(ref)[i] = N_VGetArrayPointer(ours)[i] = u(rng);
  }
  ~Pair() {
    N_VDestroy(ref);
    N_VDestroy(ours);
  }
  Pair(const Pair&) = delete;
  Pair& operator=(const Pair&) = delete;
};

}  // namespace

TEST_CASE("rigidae's serial vector: the same bits as NVECTOR_SERIAL in every operation") {
  Context c;
  std::mt19937 rng(20261124);
  const double coeffs[] = {1.0, -1.0, 0.3, -0.3, 0.7, 2.5, 0.0};
  for (sunindextype n = 1; n <= 20; ++n) {
    CAPTURE(n);
    Pair x(n, c.ctx, rng), y(n, c.ctx, rng), z(n, c.ctx, rng), w(n, c.ctx, rng, 0.1, 2.0);
    Pair id(n, c.ctx, rng), cons(n, c.ctx, rng);
    for (sunindextype i = 0; i < n; ++i) {  // a mask with zeros, and constraint codes -2..2
      N_VGetArrayPointer(id.ref)[i] = N_VGetArrayPointer(id.ours)[i] = (i % 3 == 1) ? 0.0 : 1.0;
      N_VGetArrayPointer(cons.ref)[i] = N_VGetArrayPointer(cons.ours)[i] = static_cast<double>(i % 5) - 2.0;
    }
    N_VGetArrayPointer(y.ref)[0] = N_VGetArrayPointer(y.ours)[0] = 0.0;  // a zero for inv_test / min_quotient

    // N_VLinearSum with every special case, in place and not.
    for (double a : coeffs)
      for (double b : coeffs) {
        CAPTURE(a);
        CAPTURE(b);
        N_VLinearSum(a, x.ref, b, y.ref, z.ref);
        N_VLinearSum(a, x.ours, b, y.ours, z.ours);
        CHECK(same_bits(z.ref, z.ours));
        N_VLinearSum(a, x.ref, b, z.ref, z.ref);  // z = a x + b z
        N_VLinearSum(a, x.ours, b, z.ours, z.ours);
        CHECK(same_bits(z.ref, z.ours));
        N_VLinearSum(a, z.ref, b, y.ref, z.ref);  // z = a z + b y
        N_VLinearSum(a, z.ours, b, y.ours, z.ours);
        CHECK(same_bits(z.ref, z.ours));
        N_VScale(a, x.ref, z.ref);
        N_VScale(a, x.ours, z.ours);
        CHECK(same_bits(z.ref, z.ours));
        N_VScale(b, z.ref, z.ref);
        N_VScale(b, z.ours, z.ours);
        CHECK(same_bits(z.ref, z.ours));
      }

    auto elementwise = [&](auto op) {
      op(z.ref, x.ref, y.ref, w.ref);
      op(z.ours, x.ours, y.ours, w.ours);
      CHECK(same_bits(z.ref, z.ours));
    };
    elementwise([](N_Vector z_, N_Vector x_, N_Vector y_, N_Vector) { N_VProd(x_, y_, z_); });
    elementwise([](N_Vector z_, N_Vector x_, N_Vector, N_Vector w_) { N_VDiv(x_, w_, z_); });
    elementwise([](N_Vector z_, N_Vector x_, N_Vector, N_Vector) { N_VAbs(x_, z_); });
    elementwise([](N_Vector z_, N_Vector, N_Vector, N_Vector w_) { N_VInv(w_, z_); });
    elementwise([](N_Vector z_, N_Vector x_, N_Vector, N_Vector) { N_VAddConst(x_, 0.37, z_); });
    elementwise([](N_Vector z_, N_Vector, N_Vector, N_Vector) { N_VConst(-1.25, z_); });
    elementwise([](N_Vector z_, N_Vector x_, N_Vector, N_Vector) { N_VCompare(1.1, x_, z_); });

    CHECK(same_bits(N_VDotProd(x.ref, y.ref), N_VDotProd(x.ours, y.ours)));
    CHECK(same_bits(N_VMaxNorm(x.ref), N_VMaxNorm(x.ours)));
    CHECK(same_bits(N_VWrmsNorm(x.ref, w.ref), N_VWrmsNorm(x.ours, w.ours)));
    CHECK(same_bits(N_VWrmsNormMask(x.ref, w.ref, id.ref), N_VWrmsNormMask(x.ours, w.ours, id.ours)));
    CHECK(same_bits(N_VMin(x.ref), N_VMin(x.ours)));
    CHECK(same_bits(N_VWL2Norm(x.ref, w.ref), N_VWL2Norm(x.ours, w.ours)));
    CHECK(same_bits(N_VL1Norm(x.ref), N_VL1Norm(x.ours)));
    CHECK(same_bits(N_VMinQuotient(x.ref, y.ref), N_VMinQuotient(x.ours, y.ours)));
    CHECK(N_VInvTest(y.ref, z.ref) == N_VInvTest(y.ours, z.ours));
    CHECK(same_bits(z.ref, z.ours));
    CHECK(N_VConstrMask(cons.ref, x.ref, z.ref) == N_VConstrMask(cons.ours, x.ours, z.ours));
    CHECK(same_bits(z.ref, z.ours));

    // Fused operations against SUNDIALS' fallbacks (fused off on ref).
    Pair v0(n, c.ctx, rng), v1(n, c.ctx, rng), v2(n, c.ctx, rng), v3(n, c.ctx, rng);
    double cc[] = {0.5, -1.0, 1.0, 0.25};
    for (int nvec = 1; nvec <= 4; ++nvec) {
      N_Vector Xr[] = {v0.ref, v1.ref, v2.ref, v3.ref}, Xo[] = {v0.ours, v1.ours, v2.ours, v3.ours};
      N_VLinearCombination(nvec, cc, Xr, z.ref);
      N_VLinearCombination(nvec, cc, Xo, z.ours);
      CHECK(same_bits(z.ref, z.ours));
      // In place, z among the inputs (IDA's predictor does this).
      N_Vector Zr[] = {z.ref, v1.ref, v2.ref, v3.ref}, Zo[] = {z.ours, v1.ours, v2.ours, v3.ours};
      N_VLinearCombination(nvec, cc, Zr, z.ref);
      N_VLinearCombination(nvec, cc, Zo, z.ours);
      CHECK(same_bits(z.ref, z.ours));
      N_VScaleAddMulti(nvec, cc, x.ref, Xr, Xr);
      N_VScaleAddMulti(nvec, cc, x.ours, Xo, Xo);
      for (int k = 0; k < nvec; ++k) CHECK(same_bits(Xr[k], Xo[k]));
      double dr[4], dq[4], nr[4], nq[4];
      N_VDotProdMulti(nvec, x.ref, Xr, dr);
      N_VDotProdMulti(nvec, x.ours, Xo, dq);
      N_Vector Wr[] = {w.ref, w.ref, w.ref, w.ref}, Wo[] = {w.ours, w.ours, w.ours, w.ours};
      N_VWrmsNormVectorArray(nvec, Xr, Wr, nr);
      N_VWrmsNormVectorArray(nvec, Xo, Wo, nq);
      for (int k = 0; k < nvec; ++k) CHECK((same_bits(dr[k], dq[k]) && same_bits(nr[k], nq[k])));
      N_VWrmsNormMaskVectorArray(nvec, Xr, Wr, id.ref, nr);
      N_VWrmsNormMaskVectorArray(nvec, Xo, Wo, id.ours, nq);
      for (int k = 0; k < nvec; ++k) CHECK(same_bits(nr[k], nq[k]));
      N_Vector Yr[] = {y.ref, x.ref, y.ref, x.ref}, Yo[] = {y.ours, x.ours, y.ours, x.ours};
      N_VLinearSumVectorArray(nvec, 0.5, Yr, 0.5, Xr, Xr);  // the a = b case
      N_VLinearSumVectorArray(nvec, 0.5, Yo, 0.5, Xo, Xo);
      N_VScaleVectorArray(nvec, cc, Xr, Xr);
      N_VScaleVectorArray(nvec, cc, Xo, Xo);
      for (int k = 0; k < nvec; ++k) CHECK(same_bits(Xr[k], Xo[k]));
      // Vector arrays of sums: two right-hand sides, nvec terms each.
      N_Vector* XXr[] = {Xr, Yr}; N_Vector* XXo[] = {Xo, Yo};
      N_Vector Or[] = {z.ref, w.ref}, Oo[] = {z.ours, w.ours};
      N_VLinearCombinationVectorArray(2, nvec >= 2 ? 2 : 1, cc, XXr, Or);
      N_VLinearCombinationVectorArray(2, nvec >= 2 ? 2 : 1, cc, XXo, Oo);
      CHECK((same_bits(z.ref, z.ours) && same_bits(w.ref, w.ours)));
    }
  }
}

TEST_CASE("rigidae's serial vector: ARKODE-sized linear combinations (zero coefficients, up to 14 terms) bit for bit") {
  // An explicit Runge-Kutta stage: z = 1 * y_n + sum_j h a_ij F_j, with the
  // zeros of a sparse table among the a_ij, on every length 1..20 (the
  // fixed-length kernels up to 16 and the general loop beyond).
  Context c;
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (sunindextype n = 1; n <= 20; ++n) {
    CAPTURE(n);
    std::vector<std::unique_ptr<Pair>> v;
    for (int k = 0; k < 14; ++k) v.push_back(std::make_unique<Pair>(n, c.ctx, rng));
    Pair z(n, c.ctx, rng);
    for (int nvec = 1; nvec <= 14; ++nvec) {
      CAPTURE(nvec);
      double cc[14];
      N_Vector Xr[14], Xo[14];
      for (int k = 0; k < nvec; ++k) {
        cc[k] = (k % 3 == 2) ? 0.0 : 1e-3 * u(rng);  // every third coefficient zero
        Xr[k] = v[k]->ref;
        Xo[k] = v[k]->ours;
      }
      cc[0] = 1.0;
      N_VLinearCombination(nvec, cc, Xr, z.ref);
      N_VLinearCombination(nvec, cc, Xo, z.ours);
      CHECK(same_bits(z.ref, z.ours));
      // z as the first term (allowed in the fixed kernels) and as a later one (the general loop).
      Xr[0] = z.ref, Xo[0] = z.ours;
      N_VLinearCombination(nvec, cc, Xr, z.ref);
      N_VLinearCombination(nvec, cc, Xo, z.ours);
      CHECK(same_bits(z.ref, z.ours));
      if (nvec >= 2) {
        Xr[nvec - 1] = z.ref, Xo[nvec - 1] = z.ours;
        N_VLinearCombination(nvec, cc, Xr, z.ref);
        N_VLinearCombination(nvec, cc, Xo, z.ours);
        CHECK(same_bits(z.ref, z.ours));
      }
    }
  }
}

TEST_CASE("rigidae's dense LU: the same factors and solutions as SUNLinSol_Dense, and a solution") {
  Context c;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (sunindextype n : {1, 2, 3, 7, 8, 12, 16, 17, 25}) {
    CAPTURE(n);
    SUNMatrix Ar = SUNDenseMatrix(n, n, c.ctx), Ao = SUNDenseMatrix(n, n, c.ctx);
    N_Vector br = N_VNew_Serial(n, c.ctx), xr = N_VNew_Serial(n, c.ctx);
    N_Vector bo = rigidae::sun::new_serial_vector(n, c.ctx), xo = rigidae::sun::new_serial_vector(n, c.ctx);
    SUNLinearSolver Lr = SUNLinSol_Dense(br, Ar, c.ctx);
    SUNLinearSolver Lo = rigidae::sun::new_dense_lu_solver(bo, Ao, c.ctx);
    REQUIRE(Lo != nullptr);
    std::vector<double> A0(static_cast<std::size_t>(n * n));
    for (int trial = 0; trial < 5; ++trial) {
      // Small diagonal, so that pivoting happens; a zero entry or two too.
      for (sunindextype k = 0; k < n * n; ++k) A0[k] = (k % (n + 1) == 0) ? 1e-3 * u(rng) : u(rng);
      if (n > 2) A0[1] = 0.0;
      std::copy(A0.begin(), A0.end(), SUNDenseMatrix_Data(Ar));
      std::copy(A0.begin(), A0.end(), SUNDenseMatrix_Data(Ao));
      for (sunindextype i = 0; i < n; ++i) N_VGetArrayPointer(br)[i] = N_VGetArrayPointer(bo)[i] = u(rng);
      REQUIRE(SUNLinSolSetup(Lr, Ar) == 0);
      REQUIRE(SUNLinSolSetup(Lo, Ao) == 0);
      for (sunindextype k = 0; k < n * n; ++k)
        CHECK(same_bits(SUNDenseMatrix_Data(Ar)[k], SUNDenseMatrix_Data(Ao)[k]));
      REQUIRE(SUNLinSolSolve(Lr, Ar, xr, br, 0.0) == 0);
      REQUIRE(SUNLinSolSolve(Lo, Ao, xo, bo, 0.0) == 0);
      CHECK(same_bits(xr, xo));
      // And it solves A x = b.
      double res = 0.0, scale = 0.0;
      for (sunindextype i = 0; i < n; ++i) {
        double r = -N_VGetArrayPointer(bo)[i];
        for (sunindextype j = 0; j < n; ++j) r += A0[j * n + i] * N_VGetArrayPointer(xo)[j];
        res = std::max(res, std::abs(r));
        scale = std::max(scale, std::abs(N_VGetArrayPointer(xo)[i]));
      }
      CHECK(res <= 1e-11 * std::max(1.0, scale) * static_cast<double>(n));
    }
    // A singular matrix (a zero column): both report the failed column.
    std::fill(SUNDenseMatrix_Data(Ar), SUNDenseMatrix_Data(Ar) + n * n, 1.0);
    std::fill(SUNDenseMatrix_Data(Ao), SUNDenseMatrix_Data(Ao) + n * n, 1.0);
    for (sunindextype i = 0; i < n; ++i) SUNDenseMatrix_Data(Ar)[i] = SUNDenseMatrix_Data(Ao)[i] = 0.0;
    CHECK(SUNLinSolSetup(Lr, Ar) == SUNLS_LUFACT_FAIL);
    CHECK(SUNLinSolSetup(Lo, Ao) == SUNLS_LUFACT_FAIL);
    CHECK(SUNLinSolLastFlag(Lr) == SUNLinSolLastFlag(Lo));
    SUNLinSolFree(Lr);
    SUNLinSolFree(Lo);
    for (N_Vector v : {br, xr, bo, xo}) N_VDestroy(v);
    SUNMatDestroy(Ar);
    SUNMatDestroy(Ao);
  }
}

TEST_SUITE_END();
