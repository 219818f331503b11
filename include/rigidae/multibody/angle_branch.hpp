#pragma once
// The branch of a joint angle theta = atan2(S, C) that continues the motion
// (a revolute joint's recorded angle, a torsional spring's angle), counting
// whole turns.
//
// The angle is known at the last accepted step (value, rate, time t_n, and
// the step h_n that reached it). At the next accepted step (time t) the
// continued angle is the branch of atan2 nearest the trapezoidal prediction
//   theta_pred = value + (rate + rate_now) (t - t_n) / 2,
// and so is any evaluation within two steps of t_n (the Newton iterates of
// the next step, an output row interpolated in the last one): not the branch
// nearest the last value, which would count a step that turns the joint by
// more than pi (a smooth motion that BDF integrates almost exactly takes
// long steps) as a turn back. The prediction's error is O(h^3) in the
// angle's third derivative, far below pi for any step the integrator
// accepts. Further away (a report evaluated without its time, at t = 0) and
// before the first step: the branch nearest the last value.
#include <cmath>
#include <numbers>

namespace rigidae::multibody {

struct AngleBranch {
  double value = 0.0;  // rad, at the last accepted step
  double rate = 0.0;   // rad/s
  double t = 0.0;      // s
  double h = -1.0;     // s, the step that reached it (< 0: no step yet)

  double continued(double raw, double rate_now, double t_now) const {
    const bool near = h > 0.0 && std::abs(t_now - t) <= 2.0 * h;
    return nearest(raw, near ? predicted(rate_now, t_now) : value);
  }
  // At an accepted step (t_now its time, after the start's t): the prediction
  // across the step, however long.
  void accept(double raw, double rate_now, double t_now) {
    const bool stepped = started && t_now > t;
    const double v = nearest(raw, stepped ? predicted(rate_now, t_now) : value);
    if (stepped) h = t_now - t;
    value = v;
    rate = rate_now;
    t = t_now;
    started = true;
  }
  void reset() { *this = AngleBranch{}; }

  bool started = false;  // accept() seen (the start's state counts)

 private:
  double predicted(double rate_now, double t_now) const { return value + 0.5 * (rate + rate_now) * (t_now - t); }
  static double nearest(double raw, double guess) {
    return guess + std::remainder(raw - guess, 2.0 * std::numbers::pi);
  }
};

}  // namespace rigidae::multibody
