#pragma once
// rigidae's dense direct linear solver for SUNDIALS: LU with partial
// pivoting of a SUNDIALS dense matrix (SUNDenseMatrix), compiled by rigidae.
//
// Replaces SUNLinSol_Dense, whose library Debian builds without
// optimisation (one 8x8 back-substitution took 1,930 instructions). The
// factorisation and the solve perform the operations of SUNDIALS 6.4's
// denseGETRF / denseGETRS in the same order (the pivot is the first entry of
// largest magnitude; the column below the pivot is scaled by the reciprocal
// of the pivot; the trailing update goes column by column; the solve
// permutes, then forward and back substitutes), so a run takes the same
// steps to the last bit. Sizes up to kMaxFixedSize are compiled with the
// size known (unrolled loops); larger ones use the same loops at run time.
//
// The matrix stays SUNDIALS' dense matrix, so Jacobian callbacks keep
// writing into SUNDenseMatrix_Data and IDA's and CVODE's own matrix
// operations (zero, copy, scale-add-identity) are unchanged.
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

namespace rigidae::sun {

constexpr int kMaxFixedSize = 16;

// A new solver for the n x n dense matrix A (nullptr when out of memory).
// Free with SUNLinSolFree. The vector y is a template (its length is checked).
SUNLinearSolver new_dense_lu_solver(N_Vector y, SUNMatrix A, SUNContext ctx);

// The kernels, on column pointers cols[j][i] = A(i, j) of an n x n matrix
// (exposed for tests). lu_factor returns 0, or k + 1 when the pivot of
// column k is exactly zero (SUNDIALS' convention); pivots[k] is the row
// swapped with row k.
sunindextype lu_factor(double** cols, sunindextype n, sunindextype* pivots);
void lu_solve(double** cols, sunindextype n, const sunindextype* pivots, double* b);

}  // namespace rigidae::sun
