// Dense LU with partial pivoting for SUNDIALS (see dense_lu_solver.hpp: the
// operations and their order are those of SUNDIALS 6.4's denseGETRF and
// denseGETRS, so results are bit-identical to SUNLinSol_Dense).
#include "dense_lu_solver.hpp"

#include <sunmatrix/sunmatrix_dense.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <new>
#include <utility>

namespace rigidae::sun {

namespace {

using Index = sunindextype;

// N > 0: the size known at compile time; N == 0: n at run time.
template <Index N>
Index factor(double** a, Index n_run, Index* p) {
  const Index n = N > 0 ? N : n_run;
  for (Index k = 0; k < n; ++k) {
    double* col_k = a[k];
    Index l = k;
    for (Index i = k + 1; i < n; ++i)
      if (std::fabs(col_k[i]) > std::fabs(col_k[l])) l = i;
    p[k] = l;
    if (col_k[l] == 0.0) return k + 1;
    if (l != k)
      for (Index j = 0; j < n; ++j) {
        const double t = a[j][l];
        a[j][l] = a[j][k];
        a[j][k] = t;
      }
    const double mult = 1.0 / col_k[k];
    for (Index i = k + 1; i < n; ++i) col_k[i] *= mult;
    for (Index j = k + 1; j < n; ++j) {
      double* col_j = a[j];
      const double a_kj = col_j[k];
      if (a_kj != 0.0)
        for (Index i = k + 1; i < n; ++i) col_j[i] -= a_kj * col_k[i];
    }
  }
  return 0;
}

template <Index N>
void solve(double** a, Index n_run, const Index* p, double* b) {
  const Index n = N > 0 ? N : n_run;
  for (Index k = 0; k < n; ++k) {
    const Index pk = p[k];
    if (pk != k) {
      const double t = b[k];
      b[k] = b[pk];
      b[pk] = t;
    }
  }
  for (Index k = 0; k < n - 1; ++k) {
    const double* col_k = a[k];
    const double bk = b[k];
    for (Index i = k + 1; i < n; ++i) b[i] -= col_k[i] * bk;
  }
  for (Index k = n - 1; k > 0; --k) {
    const double* col_k = a[k];
    b[k] /= col_k[k];
    const double bk = b[k];
    for (Index i = 0; i < k; ++i) b[i] -= col_k[i] * bk;
  }
  b[0] /= a[0][0];
}

using FactorFn = Index (*)(double**, Index, Index*);
using SolveFn = void (*)(double**, Index, const Index*, double*);

template <Index... Ns>
constexpr std::array<FactorFn, sizeof...(Ns)> factor_table(std::integer_sequence<Index, Ns...>) {
  return {&factor<Ns>...};
}
template <Index... Ns>
constexpr std::array<SolveFn, sizeof...(Ns)> solve_table(std::integer_sequence<Index, Ns...>) {
  return {&solve<Ns>...};
}
// Entry 0 is the run-time size; entry n the size n.
constexpr auto kFactor = factor_table(std::make_integer_sequence<Index, kMaxFixedSize + 1>{});
constexpr auto kSolve = solve_table(std::make_integer_sequence<Index, kMaxFixedSize + 1>{});

struct Content {
  Index n = 0;
  Index* pivots = nullptr;
  FactorFn factor = nullptr;
  SolveFn solve = nullptr;
  Index last_flag = 0;
};

Content* content(SUNLinearSolver S) { return static_cast<Content*>(S->content); }

SUNLinearSolver_Type get_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID get_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }

int initialize(SUNLinearSolver S) {
  content(S)->last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

int setup(SUNLinearSolver S, SUNMatrix A) {
  Content* c = content(S);
  if (!A || SUNMatGetID(A) != SUNMATRIX_DENSE || SM_ROWS_D(A) != c->n || SM_COLUMNS_D(A) != c->n) {
    c->last_flag = SUNLS_ILL_INPUT;
    return SUNLS_ILL_INPUT;
  }
  c->last_flag = c->factor(SM_COLS_D(A), c->n, c->pivots);
  return c->last_flag > 0 ? SUNLS_LUFACT_FAIL : SUNLS_SUCCESS;
}

int solve_op(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, sunrealtype /*tol*/) {
  Content* c = content(S);
  double* xd = N_VGetArrayPointer(x);
  const double* bd = N_VGetArrayPointer(b);
  if (!A || !xd || !bd) {
    c->last_flag = SUNLS_MEM_NULL;
    return SUNLS_MEM_NULL;
  }
  if (xd != bd)
    for (Index i = 0; i < c->n; ++i) xd[i] = bd[i];
  c->solve(SM_COLS_D(A), c->n, c->pivots, xd);
  c->last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

sunindextype last_flag(SUNLinearSolver S) { return content(S)->last_flag; }

int space(SUNLinearSolver S, long* lenrw, long* leniw) {
  *lenrw = 0;
  *leniw = 2 + content(S)->n;
  return SUNLS_SUCCESS;
}

int free_op(SUNLinearSolver S) {
  if (!S) return SUNLS_SUCCESS;
  if (Content* c = content(S)) {
    std::free(c->pivots);
    delete c;
    S->content = nullptr;
  }
  SUNLinSolFreeEmpty(S);
  return SUNLS_SUCCESS;
}

}  // namespace

sunindextype lu_factor(double** cols, sunindextype n, sunindextype* pivots) {
  return n <= kMaxFixedSize ? kFactor[n](cols, n, pivots) : factor<0>(cols, n, pivots);
}

void lu_solve(double** cols, sunindextype n, const sunindextype* pivots, double* b) {
  if (n <= kMaxFixedSize)
    kSolve[n](cols, n, pivots, b);
  else
    solve<0>(cols, n, pivots, b);
}

SUNLinearSolver new_dense_lu_solver(N_Vector y, SUNMatrix A, SUNContext ctx) {
  if (!y || !A || SUNMatGetID(A) != SUNMATRIX_DENSE) return nullptr;
  const Index n = SM_ROWS_D(A);
  if (SM_COLUMNS_D(A) != n || N_VGetLength(y) != n || n < 1) return nullptr;
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (!S) return nullptr;
  S->ops->gettype = get_type;
  S->ops->getid = get_id;
  S->ops->initialize = initialize;
  S->ops->setup = setup;
  S->ops->solve = solve_op;
  S->ops->lastflag = last_flag;
  S->ops->space = space;
  S->ops->free = free_op;
  auto* c = new (std::nothrow) Content;
  if (!c) {
    SUNLinSolFreeEmpty(S);
    return nullptr;
  }
  S->content = c;
  c->n = n;
  c->pivots = static_cast<Index*>(std::malloc(sizeof(Index) * static_cast<std::size_t>(n)));
  if (!c->pivots) {
    free_op(S);
    return nullptr;
  }
  c->factor = n <= kMaxFixedSize ? kFactor[n] : &factor<0>;
  c->solve = n <= kMaxFixedSize ? kSolve[n] : &solve<0>;
  return S;
}

}  // namespace rigidae::sun
