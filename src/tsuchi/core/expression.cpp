#include "tsuchi/core/expression.hpp"

#include <muParser.h>

#include <numbers>
#include <stdexcept>
#include <string_view>

namespace tsuchi {

struct Expression::Impl {
  mu::Parser parser;
  // muparser binds variables by address; they live here and are set before each evaluation.
  double x = 0.0, y = 0.0, z = 0.0, t = 0.0;
};

Expression::Expression(const std::string& formula, Of variables) : impl_(std::make_unique<Impl>()) {
  try {
    if (variables == Of::Position) {
      impl_->parser.DefineVar("x", &impl_->x);
      impl_->parser.DefineVar("y", &impl_->y);
      impl_->parser.DefineVar("z", &impl_->z);
    } else {
      impl_->parser.DefineVar("t", &impl_->t);
    }
    impl_->parser.DefineConst("pi", std::numbers::pi);
    // muparser takes "x = 5" as an assignment to x and "1, 2" as two results (of which Eval gives
    // the last): neither is a formula of x, y, z giving one value.
    for (std::size_t i = 0; i < formula.size(); ++i)
      if (formula[i] == '=' && (i + 1 >= formula.size() || formula[i + 1] != '=') &&
          (i == 0 || std::string_view("=<>!").find(formula[i - 1]) == std::string_view::npos))
        throw std::invalid_argument(variables == Of::Position
                                        ? "an assignment ('=') is not a formula; write the value itself, e.g. \"0.1 * x\""
                                        : "an assignment ('=') is not a formula; write the value itself, e.g. \"min(t / 2, 1)\"");
    impl_->parser.SetExpr(formula);
    impl_->parser.Eval();  // parses now, so a bad formula fails at input time
    if (impl_->parser.GetNumResults() != 1)
      throw std::invalid_argument("it gives several values separated by ','; a formula gives one value");
  } catch (const mu::Parser::exception_type& e) {
    throw std::invalid_argument(e.GetMsg());
  }
}

Expression::~Expression() = default;
Expression::Expression(Expression&&) noexcept = default;
Expression& Expression::operator=(Expression&&) noexcept = default;

double Expression::operator()(double x, double y, double z) const {
  impl_->x = x;
  impl_->y = y;
  impl_->z = z;
  return impl_->parser.Eval();
}

double Expression::at_time(double t) const {
  impl_->t = t;
  return impl_->parser.Eval();
}

}  // namespace tsuchi
