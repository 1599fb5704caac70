// Exact coefficient expressions of method files (docs/method-files.md): a small recursive-descent
// parser evaluated in long double, so that "1/2 - sqrt(3)/6" is rounded to double once, at the
// end, like the generated tableaux of src/methods/tableaux.cpp.
//
// Grammar (whitespace between tokens is ignored):
//   expr   := term   (('+' | '-') term)*
//   term   := factor (('*' | '/') factor)*
//   factor := ('+' | '-') factor | number | 'sqrt' '(' expr ')' | '(' expr ')'
//   number := digits ['.' digits] | '.' digits          (no exponent, no other name)
// Nothing else is accepted: no powers, no other functions, no variables. Division by zero, the
// square root of a negative number and a result that is not a finite double are errors.
#pragma once

#include <stdexcept>
#include <string>

namespace dampsym {

struct CoefficientExprError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

// The value of `text` in long double; CoefficientExprError (with the position) if it is not an
// expression of the grammar above or its value is not finite.
long double evaluate_coefficient_expr(const std::string& text);

} // namespace dampsym
