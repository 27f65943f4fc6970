#pragma once
// A scalar formula of position, such as "0.1 * sin(pi * x / 2)", for fields a user sets up once
// (initial velocities). Variables x, y, z (m) and the constant pi; functions as in muparser
// (sin, cos, exp, sqrt, abs, min, max, ...). Evaluated at set-up, never in a time step.
#include <memory>
#include <string>

namespace tsuchi {

class Expression {
 public:
  // Throws std::invalid_argument with the parser's message if the formula is not valid.
  explicit Expression(const std::string& formula);
  ~Expression();
  Expression(Expression&&) noexcept;
  Expression& operator=(Expression&&) noexcept;

  double operator()(double x, double y, double z) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tsuchi
