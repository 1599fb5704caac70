// A stepper of any kernel behind a virtual call: what the diagnostics' separate passes step (the
// E_n pass with its Jacobian check, the one step of the local error, the unit vectors of the
// one-step matrix). Those passes are then compiled once per problem instead of once per (kernel,
// problem) pair; the kernel itself is compiled once per pair, in the library's kernel shards
// (harness/run/kernel_ops.hpp). The measured run's step loop is not this: it stays typed, with no
// virtual call per step (core/integrate.hpp).
#pragma once

#include "core/method.hpp"
#include "core/types.hpp"

#include <memory>
#include <stdexcept>
#include <string>

namespace dampsym {

// Whether kernel K computes its exact step Jacobian Ψ = ∂z₁/∂z₀ (step_jacobian).
template <class K>
constexpr bool kernel_has_step_jacobian() {
    if constexpr (requires { K::has_step_jacobian; })
        return K::has_step_jacobian;
    else
        return false;
}

class AnyStepper {
public:
    virtual ~AnyStepper() = default;
    // One step from (t, z): z becomes the state at t + h (the kernel's step).
    virtual StepStatus step(double t, Vec& z) = 0;
    // As step(), with the same arithmetic on z, and Ψ = ∂z₁/∂z₀; only where has_step_jacobian().
    virtual StepStatus step_jacobian(double t, Vec& z, Mat& Psi) = 0;
    virtual bool has_step_jacobian() const = 0;
    // How step_jacobian obtains Ψ: "exact", or for a C plugin's method "plugin-jacobian" /
    // "central-differences" (methods/plugin_kernel.hpp).
    virtual const char* jacobian_source() const = 0;
};

// Kernel K behind AnyStepper (constructed as the run constructs it: problem, row, h, counters).
template <class K>
class StepperOf final : public AnyStepper {
public:
    template <class P>
    StepperOf(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : k_(problem, info, h, counters) {}
    StepStatus step(double t, Vec& z) override { return k_.step(t, z); }
    StepStatus step_jacobian(double t, Vec& z, Mat& Psi) override {
        if constexpr (kernel_has_step_jacobian<K>())
            return k_.step_jacobian(t, z, Psi);
        else
            throw std::logic_error("kernel " + std::string(K::kernel_id) + " has no step Jacobian");
    }
    bool has_step_jacobian() const override { return kernel_has_step_jacobian<K>(); }
    const char* jacobian_source() const override {
        if constexpr (requires { k_.jacobian_source(); })
            return k_.jacobian_source();
        else
            return "exact";
    }
    K& kernel() { return k_; }

private:
    K k_;
};

// How a pass makes steppers of the run's kernel on problem type P (a fresh stepper each call, with
// its own state and counters), and whether they have a step Jacobian (known without making one).
template <class P>
struct StepperMaker {
    std::unique_ptr<AnyStepper> (*make)(const P&, const MethodInfo&, double h, Counters&) = nullptr;
    bool has_step_jacobian = false;
    std::unique_ptr<AnyStepper> operator()(const P& problem, const MethodInfo& info, double h,
                                           Counters& counters) const {
        return make(problem, info, h, counters);
    }
};

template <class K, class P>
std::unique_ptr<AnyStepper> make_stepper_of(const P& problem, const MethodInfo& info, double h,
                                            Counters& counters) {
    return std::make_unique<StepperOf<K>>(problem, info, h, counters);
}

// The maker of kernel K's steppers on P (for a kernel a test defines itself; the registered
// kernels' makers come compiled from the library: kernel_ops<P>, harness/run/kernel_ops.hpp).
template <class K, class P>
constexpr StepperMaker<P> stepper_maker() {
    return {&make_stepper_of<K, P>, kernel_has_step_jacobian<K>()};
}

} // namespace dampsym
