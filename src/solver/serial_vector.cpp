// rigidae's serial vector operations (see serial_vector.hpp for why and for
// the rule: the entry-wise arithmetic of NVECTOR_SERIAL 6.4 and of SUNDIALS'
// generic fallbacks for the fused operations, so that runs are bit-identical).
#include "serial_vector.hpp"

#include <array>
#include <cmath>
#include <utility>

namespace rigidae::sun {

namespace {

using Index = sunindextype;

inline Index len(N_Vector v) { return NV_LENGTH_S(v); }
inline double* dat(N_Vector v) { return NV_DATA_S(v); }

// z = a x + b y with NVECTOR_SERIAL's case analysis: the cases differ in
// rounding only where they compute c (x + y) or c (x - y) instead of
// a x + b y; every other case is a x + b y exactly (a factor +-1 is exact).
void linear_sum(double a, N_Vector x, double b, N_Vector y, N_Vector z) {
  const Index n = len(x);
  const double* xd = dat(x);
  const double* yd = dat(y);
  double* zd = dat(z);
  const bool a1 = a == 1.0, b1 = b == 1.0, am1 = a == -1.0, bm1 = b == -1.0;
  if (b1 && z == y) {  // y += a x
    for (Index i = 0; i < n; ++i) zd[i] = zd[i] + a * xd[i];
    return;
  }
  if (a1 && z == x) {  // x += b y
    for (Index i = 0; i < n; ++i) zd[i] = zd[i] + b * yd[i];
    return;
  }
  if (a1 || b1 || am1 || bm1) {
    // x + y, x - y, a x + y, a x - y and their mirrors: each is a x + b y
    // with one factor +-1, hence exactly a x + b y.
    for (Index i = 0; i < n; ++i) zd[i] = a * xd[i] + b * yd[i];
    return;
  }
  if (a == b) {
    for (Index i = 0; i < n; ++i) zd[i] = a * (xd[i] + yd[i]);
    return;
  }
  if (a == -b) {
    for (Index i = 0; i < n; ++i) zd[i] = a * (xd[i] - yd[i]);
    return;
  }
  for (Index i = 0; i < n; ++i) zd[i] = a * xd[i] + b * yd[i];
}

void constant(double c, N_Vector z) {
  double* zd = dat(z);
  for (Index i = 0, n = len(z); i < n; ++i) zd[i] = c;
}

void prod(N_Vector x, N_Vector y, N_Vector z) {
  const double *xd = dat(x), *yd = dat(y);
  double* zd = dat(z);
  for (Index i = 0, n = len(x); i < n; ++i) zd[i] = xd[i] * yd[i];
}

void div(N_Vector x, N_Vector y, N_Vector z) {
  const double *xd = dat(x), *yd = dat(y);
  double* zd = dat(z);
  for (Index i = 0, n = len(x); i < n; ++i) zd[i] = xd[i] / yd[i];
}

// c x: copy and negation for c = +-1 give the same bits.
void scale(double c, N_Vector x, N_Vector z) {
  const double* xd = dat(x);
  double* zd = dat(z);
  for (Index i = 0, n = len(x); i < n; ++i) zd[i] = c * xd[i];
}

void absolute(N_Vector x, N_Vector z) {
  const double* xd = dat(x);
  double* zd = dat(z);
  for (Index i = 0, n = len(x); i < n; ++i) zd[i] = std::fabs(xd[i]);
}

void inv(N_Vector x, N_Vector z) {
  const double* xd = dat(x);
  double* zd = dat(z);
  for (Index i = 0, n = len(x); i < n; ++i) zd[i] = 1.0 / xd[i];
}

void add_const(N_Vector x, double b, N_Vector z) {
  const double* xd = dat(x);
  double* zd = dat(z);
  for (Index i = 0, n = len(x); i < n; ++i) zd[i] = xd[i] + b;
}

// Reductions: summed in index order (the compiler does not reassociate
// without -ffast-math), as NVECTOR_SERIAL does.
double dot(N_Vector x, N_Vector y) {
  const double *xd = dat(x), *yd = dat(y);
  double s = 0.0;
  for (Index i = 0, n = len(x); i < n; ++i) s += xd[i] * yd[i];
  return s;
}

double max_norm(N_Vector x) {
  const double* xd = dat(x);
  double m = 0.0;
  for (Index i = 0, n = len(x); i < n; ++i)
    if (std::fabs(xd[i]) > m) m = std::fabs(xd[i]);
  return m;
}

double wsqr_sum(N_Vector x, N_Vector w) {
  const double *xd = dat(x), *wd = dat(w);
  double s = 0.0;
  for (Index i = 0, n = len(x); i < n; ++i) {
    const double p = xd[i] * wd[i];
    s += p * p;
  }
  return s;
}

double wsqr_sum_mask(N_Vector x, N_Vector w, N_Vector id) {
  const double *xd = dat(x), *wd = dat(w), *idd = dat(id);
  double s = 0.0;
  for (Index i = 0, n = len(x); i < n; ++i)
    if (idd[i] > 0.0) {
      const double p = xd[i] * wd[i];
      s += p * p;
    }
  return s;
}

double wrms_norm(N_Vector x, N_Vector w) { return std::sqrt(wsqr_sum(x, w) / static_cast<double>(len(x))); }

double wrms_norm_mask(N_Vector x, N_Vector w, N_Vector id) {
  return std::sqrt(wsqr_sum_mask(x, w, id) / static_cast<double>(len(x)));
}

double min(N_Vector x) {
  const double* xd = dat(x);
  double m = xd[0];
  for (Index i = 1, n = len(x); i < n; ++i)
    if (xd[i] < m) m = xd[i];
  return m;
}

double wl2_norm(N_Vector x, N_Vector w) { return std::sqrt(wsqr_sum(x, w)); }

double l1_norm(N_Vector x) {
  const double* xd = dat(x);
  double s = 0.0;
  for (Index i = 0, n = len(x); i < n; ++i) s += std::fabs(xd[i]);
  return s;
}

void compare(double c, N_Vector x, N_Vector z) {
  const double* xd = dat(x);
  double* zd = dat(z);
  for (Index i = 0, n = len(x); i < n; ++i) zd[i] = std::fabs(xd[i]) >= c ? 1.0 : 0.0;
}

sunbooleantype inv_test(N_Vector x, N_Vector z) {
  const double* xd = dat(x);
  double* zd = dat(z);
  sunbooleantype no_zero = SUNTRUE;
  for (Index i = 0, n = len(x); i < n; ++i) {
    if (xd[i] == 0.0)
      no_zero = SUNFALSE;
    else
      zd[i] = 1.0 / xd[i];
  }
  return no_zero;
}

// SUNDIALS' constraint codes: +-2 strictly positive/negative, +-1 non-strict.
sunbooleantype constr_mask(N_Vector c, N_Vector x, N_Vector m) {
  const double *cd = dat(c), *xd = dat(x);
  double* md = dat(m);
  bool ok = true;
  for (Index i = 0, n = len(x); i < n; ++i) {
    md[i] = 0.0;
    if (cd[i] == 0.0) continue;
    const bool bad = (std::fabs(cd[i]) > 1.5 && xd[i] * cd[i] <= 0.0) || (std::fabs(cd[i]) > 0.5 && xd[i] * cd[i] < 0.0);
    if (bad) {
      md[i] = 1.0;
      ok = false;
    }
  }
  return ok ? SUNTRUE : SUNFALSE;
}

double min_quotient(N_Vector num, N_Vector denom) {
  const double *nd = dat(num), *dd = dat(denom);
  bool none = true;
  double m = BIG_REAL;
  for (Index i = 0, n = len(num); i < n; ++i) {
    if (dd[i] == 0.0) continue;
    const double q = nd[i] / dd[i];
    if (none) {
      m = q;
      none = false;
    } else if (q < m) {
      m = q;
    }
  }
  return m;
}

// ---- fused operations: the entry-wise arithmetic of SUNDIALS' fallbacks ----

// z = c0 X0, then z += c_i X_i in order (X_i may alias z, as in the fallback).
// A term with c_i = 0 is skipped: z + 0 x_i is z for every finite x_i (up to
// the sign of a zero entry: -0 + 0 is +0), and ARKODE's explicit tables pass
// many zeros (Fehlberg 7(8): 23 of the 78 stage coefficients, 6 of the 13 weights).
void linear_combination_in_place(int nvec, const double* c, N_Vector* X, N_Vector z) {
  const Index n = len(z);
  double* zd = dat(z);
  const double* x0 = dat(X[0]);
  const double c0 = c[0];
  for (Index j = 0; j < n; ++j) zd[j] = c0 * x0[j];
  for (int i = 1; i < nvec; ++i) {
    const double ci = c[i];
    if (ci == 0.0) continue;
    const double* xi = dat(X[i]);
    for (Index j = 0; j < n; ++j) zd[j] = zd[j] + ci * xi[j];
  }
}

// The same sums for a length N known at compile time, entry by entry in
// registers (each entry still c0 x0 + c1 x1 + ... in the order of the terms,
// hence the same bits): the ODE integrators' stage sums on one body's 7 to 12
// states, where the loop above spends most of its time on loop and alias
// overhead. A term X_i = z (i >= 1) would have to read the partial sum (as
// the loop above does): such a call writes nothing and returns false, and
// the caller takes the loop. The check rides on the terms' own loads.
template <int N>
bool linear_combination_fixed(int nvec, const double* c, N_Vector* X, N_Vector z) {
  double acc[N];
  const double* x0 = dat(X[0]);
  for (int j = 0; j < N; ++j) acc[j] = c[0] * x0[j];
  bool aliased = false;
  for (int i = 1; i < nvec; ++i) {
    const double ci = c[i];
    if (ci == 0.0) continue;  // skipped by the loop too: z or not, it adds nothing
    aliased |= X[i] == z;
    const double* xi = dat(X[i]);
    for (int j = 0; j < N; ++j) acc[j] = acc[j] + ci * xi[j];
  }
  if (aliased) return false;
  double* zd = dat(z);
  for (int j = 0; j < N; ++j) zd[j] = acc[j];
  return true;
}

using FixedCombination = bool (*)(int, const double*, N_Vector*, N_Vector);
template <int... N>
constexpr std::array<FixedCombination, sizeof...(N)> fixed_combinations(std::integer_sequence<int, N...>) {
  return {&linear_combination_fixed<N + 1>...};
}
constexpr int kFixedLengthMax = 16;  // lengths 1..16: single bodies (7 to 18 states) and small mechanisms
constexpr auto kFixedCombinations = fixed_combinations(std::make_integer_sequence<int, kFixedLengthMax>{});

int linear_combination(int nvec, double* c, N_Vector* X, N_Vector z) {
  const auto n = static_cast<std::size_t>(len(z)) - 1;  // lengths 1..16 -> 0..15; 0 wraps to the largest
  if (n >= static_cast<std::size_t>(kFixedLengthMax) || !kFixedCombinations[n](nvec, c, X, z))
    linear_combination_in_place(nvec, c, X, z);
  return 0;
}

// Z_i = a_i x + Y_i (NVECTOR_SERIAL's N_VLinearSum(a_i, x, 1, Y_i, Z_i): one
// factor is 1, so every case is a_i x + Y_i exactly).
int scale_add_multi(int nvec, double* a, N_Vector x, N_Vector* Y, N_Vector* Z) {
  const Index n = len(x);
  const double* xd = dat(x);
  for (int i = 0; i < nvec; ++i) {
    const double* yd = dat(Y[i]);
    double* zd = dat(Z[i]);
    const double ai = a[i];
    for (Index j = 0; j < n; ++j) zd[j] = ai * xd[j] + yd[j];
  }
  return 0;
}

int dot_prod_multi(int nvec, N_Vector x, N_Vector* Y, double* dots) {
  for (int i = 0; i < nvec; ++i) dots[i] = dot(x, Y[i]);
  return 0;
}

int linear_sum_vector_array(int nvec, double a, N_Vector* X, double b, N_Vector* Y, N_Vector* Z) {
  for (int i = 0; i < nvec; ++i) linear_sum(a, X[i], b, Y[i], Z[i]);
  return 0;
}

int scale_vector_array(int nvec, double* c, N_Vector* X, N_Vector* Z) {
  for (int i = 0; i < nvec; ++i) scale(c[i], X[i], Z[i]);
  return 0;
}

int const_vector_array(int nvec, double c, N_Vector* Z) {
  for (int i = 0; i < nvec; ++i) constant(c, Z[i]);
  return 0;
}

int wrms_norm_vector_array(int nvec, N_Vector* X, N_Vector* W, double* nrm) {
  for (int i = 0; i < nvec; ++i) nrm[i] = wrms_norm(X[i], W[i]);
  return 0;
}

int wrms_norm_mask_vector_array(int nvec, N_Vector* X, N_Vector* W, N_Vector id, double* nrm) {
  for (int i = 0; i < nvec; ++i) nrm[i] = wrms_norm_mask(X[i], W[i], id);
  return 0;
}

int scale_add_multi_vector_array(int nvec, int nsum, double* a, N_Vector* X, N_Vector** Y, N_Vector** Z) {
  for (int i = 0; i < nvec; ++i) {
    const Index n = len(X[i]);
    const double* xd = dat(X[i]);
    for (int j = 0; j < nsum; ++j) {
      const double* yd = dat(Y[j][i]);
      double* zd = dat(Z[j][i]);
      const double aj = a[j];
      for (Index k = 0; k < n; ++k) zd[k] = aj * xd[k] + yd[k];
    }
  }
  return 0;
}

int linear_combination_vector_array(int nvec, int nsum, double* c, N_Vector** X, N_Vector* Z) {
  for (int i = 0; i < nvec; ++i) {
    const Index n = len(Z[i]);
    double* zd = dat(Z[i]);
    const double* x0 = dat(X[0][i]);
    for (Index k = 0; k < n; ++k) zd[k] = c[0] * x0[k];
    for (int j = 1; j < nsum; ++j) {
      const double* xj = dat(X[j][i]);
      const double cj = c[j];
      for (Index k = 0; k < n; ++k) zd[k] = zd[k] + cj * xj[k];
    }
  }
  return 0;
}

}  // namespace

N_Vector use_rigidae_operations(N_Vector v) {
  if (!v) return v;
  N_Vector_Ops o = v->ops;
  o->nvlinearsum = linear_sum;
  o->nvconst = constant;
  o->nvprod = prod;
  o->nvdiv = div;
  o->nvscale = scale;
  o->nvabs = absolute;
  o->nvinv = inv;
  o->nvaddconst = add_const;
  o->nvdotprod = dot;
  o->nvmaxnorm = max_norm;
  o->nvwrmsnorm = wrms_norm;
  o->nvwrmsnormmask = wrms_norm_mask;
  o->nvmin = min;
  o->nvwl2norm = wl2_norm;
  o->nvl1norm = l1_norm;
  o->nvcompare = compare;
  o->nvinvtest = inv_test;
  o->nvconstrmask = constr_mask;
  o->nvminquotient = min_quotient;

  o->nvlinearcombination = linear_combination;
  o->nvscaleaddmulti = scale_add_multi;
  o->nvdotprodmulti = dot_prod_multi;
  o->nvlinearsumvectorarray = linear_sum_vector_array;
  o->nvscalevectorarray = scale_vector_array;
  o->nvconstvectorarray = const_vector_array;
  o->nvwrmsnormvectorarray = wrms_norm_vector_array;
  o->nvwrmsnormmaskvectorarray = wrms_norm_mask_vector_array;
  o->nvscaleaddmultivectorarray = scale_add_multi_vector_array;
  o->nvlinearcombinationvectorarray = linear_combination_vector_array;

  o->nvdotprodlocal = dot;
  o->nvmaxnormlocal = max_norm;
  o->nvminlocal = min;
  o->nvl1normlocal = l1_norm;
  o->nvinvtestlocal = inv_test;
  o->nvconstrmasklocal = constr_mask;
  o->nvminquotientlocal = min_quotient;
  o->nvwsqrsumlocal = wsqr_sum;
  o->nvwsqrsummasklocal = wsqr_sum_mask;
  o->nvdotprodmultilocal = dot_prod_multi;
  return v;
}

N_Vector new_serial_vector(sunindextype n, SUNContext ctx) {
  // N_VClone_Serial copies the operations table, so clones made by the
  // integrators carry rigidae's operations too.
  return use_rigidae_operations(N_VNew_Serial(n, ctx));
}

}  // namespace rigidae::sun
