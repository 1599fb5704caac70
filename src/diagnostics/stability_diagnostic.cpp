#include "diagnostics/stability_diagnostic.hpp"

#include "reference/oscillator_exact.hpp"

#include <cmath>

namespace dampsym {

DiagnosticInfo StabilityDiagnostic::info() {
    return {.name = std::string(name),
            .what = "one-step matrix M on the oscillator: det, half trace, F's condition (F ch. 3)",
            .requirement = "the linear oscillator form",
            .metrics = {"det", "det_rel_err", "det_abs_err", "half_trace",
                        "half_trace_formula_rel_err", "half_trace_formula_abs_err",
                        "half_trace_exact_err", "spectral_radius", "F_condition", "power_bounded"},
            .any_status = true,
            .report_columns = {{.key = "det_rel_err", .label = "det M vs e^{−2γh} (rel)"},
                               {.key = "half_trace_formula_rel_err", .label = "½trM vs F (rel)"},
                               {.key = "spectral_radius", .label = "ρ(M)"}}};
}

DiagnosticInfo TraceTaylorDiagnostic::info() {
    return {.name = std::string(name),
            .level = DiagnosticLevel::method,
            .what = "h^4 coefficient of half tr M - e^{-gamma h} cos(beta h) (F ch. 3)",
            .requirement = "the linear oscillator form",
            .metrics = {"h4_coeff", "h4_coeff_expected", "h4_coeff_rel_err", "h4_coeff_abs_err"}};
}

json stability_metrics(const Mat& M, double omega, double g, double h, const MethodInfo& info) {
    const OneStepAnalysis a = analyse_one_step(M, g, h);
    const double det_expected = std::exp(-2.0 * g * h);
    const double exact_half_trace = oscillator_damped_cs(omega, g, h).c;
    json out = {
        {"det", a.det},
        {"det_expected", det_expected},
        {"det_rel_err", std::abs(a.det - det_expected) / det_expected},
        {"det_abs_err", std::abs(a.det - det_expected)},
        {"half_trace", a.half_trace},
        {"half_trace_exact", exact_half_trace},
        {"half_trace_exact_err", std::abs(a.half_trace - exact_half_trace)},
        {"eigenvalues", {{a.eig[0].real(), a.eig[0].imag()}, {a.eig[1].real(), a.eig[1].imag()}}},
        {"spectral_radius", a.spectral_radius},
        {"F_condition", a.F_condition ? 1 : 0},
        {"power_bounded", a.power_bounded ? 1 : 0},
        {"matrix", {{M(0, 0), M(0, 1)}, {M(1, 0), M(1, 1)}}}};
    // e^{−2γh} underflows for γh > ~354: det M against it is then round-off over nothing.
    if (!(det_expected >= std::numeric_limits<double>::min()))
        set_undefined(out, "det_rel_err", "e^{-2 gamma h} underflows: compare det_abs_err");
    const OscillatorFormulas f_of = oscillator_formulas(info.id);
    if (f_of.half_trace) {
        const double f = f_of.half_trace(omega, g, h);
        out["half_trace_formula"] = f;
        out["half_trace_formula_abs_err"] = std::abs(a.half_trace - f);
        // ½tr M passes through 0 (hω near the threshold): relative to |f| only where f is
        // resolved on the eigenvalues' scale e^{−γh}, else undefined (read the absolute error)
        const double radius = std::exp(-g * h);
        if (std::abs(f) > 1e-8 * radius && radius >= std::numeric_limits<double>::min())
            out["half_trace_formula_rel_err"] = std::abs(a.half_trace - f) / std::abs(f);
        else
            set_undefined(out, "half_trace_formula_rel_err",
                          "F's half trace is 0 on the scale e^{-gamma h}: compare "
                          "half_trace_formula_abs_err");
        out["formula_source"] = f_of.source;
    }
    return out;
}

// Leading coefficient of ½trM − e^{−γh}cos(βh) = c h⁴ + O(h⁵), by Richardson extrapolation of the
// measured (½trM − exact)/h⁴ at h = 0.02 and 0.01 (conventions §5).
json trace_taylor_metrics(const MethodInfo& info, double w, double g,
                          const HalfTraceAt& half_trace) {
    auto coeff = [&](double h) {
        return (half_trace(h) - oscillator_damped_cs(w, g, h).c) / (h * h * h * h);
    };
    const double c = std::abs(2.0 * coeff(0.01) - coeff(0.02));
    json out = {{"h4_coeff", c}};
    const OscillatorFormulas f_of = oscillator_formulas(info.id);
    if (f_of.h4_coefficient) {
        const double e = std::abs(f_of.h4_coefficient(w, g));
        out["h4_coeff_expected"] = e;
        out["h4_coeff_abs_err"] = std::abs(c - e);
        // the expected coefficient vanishes (cimp at ω = γ): no relative error
        const double scale = (w * w + g * g) * (w * w + g * g);
        if (e > 1e-12 * scale)
            out["h4_coeff_rel_err"] = std::abs(c - e) / e;
        else
            set_undefined(out, "h4_coeff_rel_err",
                          "expected h^4 coefficient is 0: compare h4_coeff_abs_err");
    }
    return out;
}

} // namespace dampsym
