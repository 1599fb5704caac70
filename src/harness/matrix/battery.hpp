// The method × property matrix, internal: the battery's property table (matrix/battery.cpp),
// shared by the battery and the judging (matrix/judge.cpp). Each property names
// its case settings (taken from the default suite's cases, cited), the metric it reads, its
// criterion, which declaration makes a method claim it and whether its negative controls must fail
// (docs/matrix.md "The battery").
#pragma once

#include "core/method.hpp"
#include "harness/case/case.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace dampsym::matrix_detail {

using json = nlohmann::json;

// How a property reads its value from the battery's report.
enum class Source {
    order,        // method_metrics[m].order.slope of the case of the method's ladder
    run,          // runs[m].metrics.<metric> of the property's single-step case
    threshold,    // method_metrics[m].stability-sweep of the sweep case
    coefficients, // the method's coefficient-level checks (no case: harness/method_coefficients)
};

struct Property {
    std::string id, header, title, source;
    Source from = Source::run;
    std::string case_id; // the battery case (order: the prefix of the ladder cases)
    std::string problem; // problem id (for method_applies)
    json case_json;      // the case's settings (problem, t_end, dt, diagnostics, ...)
    std::string metric;  // "<diagnostic>.<path>" (run); for the order/threshold sources unused
    CheckSpec criterion; // what "holds" means (op, value, tol, abs)
    unsigned claim = 0;  // the claim bit that makes a method claim the property
    bool controls_must_fail = false;
    std::string criterion_text;
};

// The battery (docs/matrix.md "The battery" lists it with the same settings and tolerances).
const std::vector<Property>& properties();

// The order ladders on the pendulum (step sizes of verify/cases/families-orders-*.json, where the
// error of a method of that order stays above the fit's floor and in the asymptotic range), and the
// ladder (its group: the order it is made for) a method of this order runs on.
std::vector<double> order_ladder(int order);
int ladder_group(int order);

// Whether method m claims property p (so a failure is a disagreement, not a negative control).
bool claims_property(const Property& p, const MethodInfo& m);

} // namespace dampsym::matrix_detail
