#pragma once
// A scalar formula, such as "0.1 * sin(pi * x / 2)": of position (x, y, z in m) for fields a user
// sets up once (initial velocities), or of time (t in s) for loads that change with time
// (core/time_function.hpp). The constant pi; functions as in muparser (sin, cos, exp, sqrt, abs,
// min, max, ...). A formula of position is evaluated at set-up only; one of time once per step.
#include <memory>
#include <string>

namespace tsuchi {

class Expression {
 public:
  // Which variables the formula may use.
  enum class Of { Position, Time };
  // Throws std::invalid_argument with the parser's message if the formula is not valid.
  explicit Expression(const std::string& formula, Of variables = Of::Position);
  ~Expression();
  Expression(Expression&&) noexcept;
  Expression& operator=(Expression&&) noexcept;

  double operator()(double x, double y, double z) const;  // Of::Position
  double at_time(double t) const;                          // Of::Time

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tsuchi
