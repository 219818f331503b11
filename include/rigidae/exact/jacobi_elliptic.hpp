#pragma once
// Jacobi elliptic functions and the elliptic integral of the first kind.
//
// Parameters: m = k^2 in [0, 1] and its complement m1 = 1 - m = k'^2, passed
// separately. Close to m = 1 (a free body near its separatrix, a top whose
// axis nearly reaches a pole) the interesting quantities are k' and 1 - k,
// which 1 - m cannot deliver once m is rounded; every routine here works from
// m1 and never forms 1 - m itself.
namespace rigidae::exact {

struct SnCnDn {
  double sn = 0.0;
  double cn = 1.0;
  double dn = 1.0;
};

// sn(u|m), cn(u|m), dn(u|m) by the descending Landen (Gauss) transformation,
// relative accuracy ~1e-15 for every real u of moderate size (the argument's
// own rounding, ~1e-16 |u|, is the limit for large |u|).
SnCnDn jacobi_sn_cn_dn(double u, double m, double m1);

// K(m) = F(pi/2 | m) by the arithmetic-geometric mean, from m1 = 1 - m
// (infinite for m1 = 0).
double complete_elliptic_k(double m1);

// F(phi | m) = integral_0^phi dt / sqrt(1 - m sin^2 t) for any real phi
// (F(phi + j pi) = F(phi) + 2 j K), the inverse of the amplitude: sn(F(phi)) = sin(phi).
double incomplete_elliptic_f(double phi, double m, double m1);

// The argument u in (-2K, 2K] with the given sn(u|m), cn(u|m), dn(u|m)
// (consistent to round-off): u = sn R_F(cn^2, dn^2, 1) for cn >= 0, continued
// through +-2K - u otherwise. Working from cn and dn themselves keeps u
// accurate where the amplitude does not: near u = K with m close to 1, an
// error e in the amplitude moves u by e/dn.
double jacobi_argument(double sn, double cn, double dn, double m1);

// Carlson's symmetric integral R_F(x, y, z) = 1/2 int_0^inf dt / sqrt((t+x)(t+y)(t+z)),
// x, y, z >= 0, at most one of them zero.
double carlson_rf(double x, double y, double z);

}  // namespace rigidae::exact
