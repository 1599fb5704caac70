// The coefficient checks of a row, from its family's traits (families.hpp).
#include "methods/families.hpp"

namespace dampsym {

std::vector<CoefficientCheck> method_checks(const MethodInfo& info) {
    std::vector<CoefficientCheck> out;
    visit_family(info,
                 [&]<class D>(Family<D>, const D& data) { Family<D>::checks(info, data, out); });
    return out;
}

} // namespace dampsym
