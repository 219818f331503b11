#pragma once
// The work W(t) = integral of a power P(t) known at the accepted steps, for
// the energy balance H - H0 - W of mechanisms with drivers and loads that
// have no potential (app/multibody_accuracy_check.hpp, the step file's
// energy_rel_error).
//
// Over each new interval [t_{n-1}, t_n] it adds the integral of the
// polynomial through the last min(n + 1, 6) values (t_k, P_k) (Gauss-Legendre
// with 4 points: exact for its degree <= 5). The error per step is
// O(h^min(n+1, 6)) times P's derivative of that order: the order of the
// integrator's own local error (BDF and Adams at order <= 5), where a
// first-order sum (sum P_n h_n) would err by O(h) P' per step. Interpolation
// only (the interval lies inside the points): stable for uneven steps.
// Allocates nothing.
namespace rigidae::multibody {

class WorkIntegral {
 public:
  // Appends (t, P); the first call only starts the integral.
  void add(double t, double P);
  // An observation y (size entries) of a problem with n unknowns: one that
  // carries W itself, as entry n (an ODE integrator integrates W' = P with
  // the state: multibody_ode.hpp), gives W; else P = power() is added.
  template <class Power>
  void follow(double t, const double* y, long size, long n, Power&& power) {
    if (carries_work(size, n))
      work_ = y[n];
    else
      add(t, power());
  }
  // Whether such an observation carries W (entry n).
  static bool carries_work(long size, long n) { return size > n; }
  // W at an observation without adding to the quadrature: its own W when it
  // carries one, else the integral up to the last accepted step.
  double value_at(const double* y, long size, long n) const { return carries_work(size, n) ? y[n] : work_; }
  double value() const { return work_; }
  void reset() { work_ = 0.0, count_ = 0; }

 private:
  static constexpr int kPoints = 6;
  double t_[kPoints] = {}, p_[kPoints] = {};
  int count_ = 0;
  double work_ = 0.0;
};

}  // namespace rigidae::multibody
