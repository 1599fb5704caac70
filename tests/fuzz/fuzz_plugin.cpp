// libFuzzer target: the plugin host's handling of the arrays it hands a plugin
// (methods/plugin_kernel.hpp, docs/plugins.md). A scripted plugin step, driven by the input,
// writes z_next at chosen indices in [-8, dim + 8) (the guard cells included, never beyond them:
// that is the ASan build's to catch), may write into its const z, call a callback outside its
// form, or refuse the step; the state dimension is chosen by the input too (1 to 64). The host's
// verdict must be exactly the one the script implies: a callback outside the form, a changed
// guard cell or a changed z is an error (std::runtime_error, the run's status `error`); then a
// refused step is solve-failed; then an element left unwritten is an error; else ok with z_next
// copied. Both the step and the central-difference step Jacobian (2d + 1 steps) are driven.
// Anything else — a wrong verdict, a crash, a sanitizer report — is a finding.
#include "core/method.hpp"
#include "dampsym/plugin.h"
#include "methods/plugin_kernel.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <vector>

namespace {

// The smallest problem the plain form needs: z' = -z, no damping.
struct FuzzProblem {
    int d = 1;
    // what the plugin kernel may ask of a problem (unused by the plain form)
    [[maybe_unused]] static constexpr bool has_conformal = false;
    [[maybe_unused]] static constexpr bool has_separable = false;
    int dim() const { return d; }
    void rhs(double, const dampsym::Vec& z, dampsym::Vec& out) const { out = -z; }
    double dGamma(double, double) const { return 0.0; }
};

struct Script {
    std::vector<int> writes; // indices written in z_next, in order (may repeat, may be outside)
    bool write_z = false, misuse = false, refuse = false;
};
Script g_script;

int scripted_step(void*, const dampsym_host* host, double, double, const double* z,
                  double* z_next) {
    for (int i : g_script.writes) z_next[i] = 0.5 * i;
    if (g_script.write_z) const_cast<double*>(z)[0] = 7.0;
    if (g_script.misuse) host->grad_T(host->host_ctx, z, z_next);
    return g_script.refuse ? 3 : 0;
}

enum class Verdict { ok, solve_failed, error };

Verdict expected(const Script& s, int d) {
    bool outside = false;
    std::vector<bool> covered(static_cast<std::size_t>(d), false);
    for (int i : s.writes) {
        if (i < 0 || i >= d)
            outside = true;
        else
            covered[static_cast<std::size_t>(i)] = true;
    }
    if (s.misuse || outside || s.write_z) return Verdict::error;
    if (s.refuse) return Verdict::solve_failed;
    for (bool c : covered)
        if (!c) return Verdict::error;
    return Verdict::ok;
}

template <class F>
Verdict observed(F&& call) {
    try {
        return call() == dampsym::StepStatus::ok ? Verdict::ok : Verdict::solve_failed;
    } catch (const std::runtime_error&) {
        return Verdict::error;
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 2) return 0;
    const int guard = static_cast<int>(dampsym::GuardedBuffer::guard);
    FuzzProblem problem;
    problem.d = 1 + data[0] % 64;
    const std::uint8_t flags = data[1];
    g_script = Script{};
    g_script.write_z = flags & 1;
    g_script.misuse = flags & 2;
    g_script.refuse = flags & 4;
    const bool jacobian = flags & 8;
    if (flags & 16) // every element first, then the input's writes
        for (int i = 0; i < problem.d; ++i) g_script.writes.push_back(i);
    for (std::size_t k = 2; k < size && k < 2 + 512; ++k)
        g_script.writes.push_back(static_cast<int>(data[k] % (problem.d + 2 * guard)) - guard);

    static const dampsym_method method{"fuzz-scripted", nullptr, 1,      DAMPSYM_FORM_PLAIN, 0,
                                       &scripted_step,  nullptr, nullptr};
    const dampsym::MethodInfo info{"fuzz-scripted",
                                   1,
                                   false,
                                   dampsym::Form::plain,
                                   dampsym::claim_none,
                                   "",
                                   dampsym::PluginStep{&method, "fuzz"}};
    dampsym::Counters counters;
    dampsym::PluginPlain<FuzzProblem> kernel(problem, info, 0.1, counters);
    dampsym::Vec z = dampsym::Vec::Constant(problem.d, 0.25);
    dampsym::Mat psi;
    const Verdict got = jacobian ? observed([&] { return kernel.step_jacobian(0.0, z, psi); })
                                 : observed([&] { return kernel.step(0.0, z); });
    if (got != expected(g_script, problem.d)) {
        std::fprintf(stderr, "fuzz finding: plugin host verdict %d, expected %d (dim %d)\n",
                     static_cast<int>(got), static_cast<int>(expected(g_script, problem.d)),
                     problem.d);
        std::abort();
    }
    return 0;
}
