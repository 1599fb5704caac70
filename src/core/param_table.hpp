// One parameter table per problem: each row is a ParamSpec (name, default, range, doc) and the
// member it sets. A problem that derives from ParamTable<P> and declares
//   static std::vector<Param<P>> param_table();
// gets param_specs() and from_params() generated from it, so a parameter's name is written once
// next to its member. An optional `void check_params() const` (throwing std::invalid_argument
// with a message starting "<id>: ") runs after the members are set.
#pragma once

#include "core/problem.hpp"

#include <vector>

namespace dampsym {

template <class P>
struct Param {
    ParamSpec spec;
    double P::*scalar = nullptr;             // a number
    std::vector<double> P::*array = nullptr; // an array parameter (spec.is_array)
};

template <class P>
struct ParamTable {
    static std::vector<ParamSpec> param_specs() {
        std::vector<ParamSpec> out;
        for (const Param<P>& p : P::param_table()) out.push_back(p.spec);
        return out;
    }
    static P from_params(const ParamMap& m) {
        P o;
        for (const Param<P>& p : P::param_table()) {
            if (p.scalar) o.*p.scalar = m.at(p.spec.name);
            if (p.array) o.*p.array = m.array(p.spec.name);
        }
        if constexpr (requires { o.check_params(); }) o.check_params();
        return o;
    }
};

} // namespace dampsym
