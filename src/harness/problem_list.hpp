// The problem registry: every problem type of dampsym, one entry each in ProblemList (a problem
// is one header satisfying core/problem_concepts.hpp). The typed case runner is instantiated for
// each (src/harness/run/typed_case.hpp); the kernels that step them are the method registry's
// (harness/registry.hpp).
#pragma once

#include "core/problem_concepts.hpp"
#include "core/types.hpp"
#include "problems/argon.hpp"
#include "problems/driven_pendulum.hpp"
#include "problems/hill.hpp"
#include "problems/kepler.hpp"
#include "problems/lotka_volterra.hpp"
#include "problems/nbody.hpp"
#include "problems/oscillator.hpp"
#include "problems/outer_solar_system.hpp"
#include "problems/pendulum.hpp"
// Damped PDEs of B ch. 4-5, semi-discretised (docs/pde.md).
#include "pde/burgers/problem.hpp"
#include "pde/klein_gordon/problem.hpp"
#include "pde/nls/problem.hpp"
#include "problems/rigid_body.hpp"

#include <string_view>

namespace dampsym {

using ProblemList = TypeList<Oscillator, Pendulum, DrivenPendulum, Hill, RigidBody, LotkaVolterra,
                             NBody, Kepler, OuterSolarSystem, Argon, KleinGordon, KleinGordonBox,
                             Burgers, BurgersBox, BurgersUpwind, Schrodinger, NLS,
                             NLSDriven>; // PDEs: B (4.3), (4.5), (4.7), docs/pde.md

// Every registered problem satisfies the problem contract (core/problem_concepts.hpp).
template <class... Ps>
constexpr bool all_problems(TypeList<Ps...>) {
    return (Problem<Ps> && ...);
}
static_assert(all_problems(ProblemList{}),
              "every problem in ProblemList must satisfy dampsym::Problem "
              "(core/problem_concepts.hpp; an exact solution takes its start (t0, z0))");

// Calls f.template operator()<P>() for the problem type with this id; false if none.
template <class F>
bool with_problem_type(std::string_view id, F&& f) {
    bool found = false;
    for_each_type(ProblemList{}, [&]<class P>() {
        if (!found && P::id == id) {
            found = true;
            f.template operator()<P>();
        }
    });
    return found;
}

} // namespace dampsym
