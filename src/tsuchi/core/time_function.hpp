#pragma once
// A function of time f(t) that scales a load: a prescribed velocity, a traction, gravity, a body
// force or a base motion is its value times f(t) (the input's [[functions]], docs/input.md).
// f = 1 when none is given. A table is interpolated linearly between its points and holds its first
// value before the first time and its last value after the last one (a record that has ended leaves
// its last value, so an acceleration record should end at 0); a formula is any expression of t.
#include "tsuchi/core/expression.hpp"

#include <memory>
#include <string>
#include <vector>

namespace tsuchi {

class TimeFunction {
 public:
  TimeFunction() = default;  // f(t) = 1
  // Times strictly increasing (the input reader checks it), at least one point.
  static TimeFunction table(std::vector<double> times, std::vector<double> values);
  // `name` and `text` (the [[functions]] entry and its formula) are for the message when the
  // formula gives a non-finite value: then operator() and integral() throw RunError (Fault::NonFinite)
  // naming the function and the time, rather than letting an infinite load reach a particle.
  static TimeFunction formula(std::shared_ptr<const Expression> of_time, std::string name = {}, std::string text = {});

  // The function started at t0 instead of 0: g(t) = f(t - t0), the clock of a load that a stage
  // sets (docs/stages.md); before t0 its integral is zero (the load did not act yet).
  TimeFunction starting_at(double t0) const {
    TimeFunction g = *this;
    g.start_ = t0;
    return g;
  }
  double start() const { return start_; }
  // When the function stops changing: a table's last time (on the run's clock); the start for
  // f = 1 and for a formula, whose future is not known.
  double settles_at() const { return kind_ == Kind::Table ? start_ + t_.back() : start_; }

  bool is_one() const { return kind_ == Kind::One; }
  double operator()(double t) const;
  // The integral of f over [a, b]: exact for a table (trapezoids between its points, so that a
  // velocity integrated from an acceleration record is the record's own integral however the time
  // steps fall), five-point Gauss-Legendre per piece for a formula (exact for polynomials of degree 9
  // over pieces no longer than a fiftieth of [a, b]).
  double integral(double a, double b) const;

 private:
  enum class Kind { One, Table, Formula };
  Kind kind_ = Kind::One;
  std::vector<double> t_, v_;
  std::shared_ptr<const Expression> f_;
  std::string name_, text_;
  double start_ = 0.0;
  double finite(double value, double t) const;  // value, or RunError naming the function and t
};

}  // namespace tsuchi
