// General linear method data (see glm_coefficients.hpp for the definitions and citations).
#include "methods/glm_coefficients.hpp"

#include <cmath>

namespace dampsym {

const GlmCoefficients& butcher_glm4() {
    static const GlmCoefficients m = [] {
        const double r3 = std::sqrt(3.0);
        const double theta = (3.0 + r3) / 6.0; // diagonal of A and A₀
        const double u = (3.0 + 2.0 * r3) / 3.0;
        GlmCoefficients g;
        g.name = "glm4";
        g.s = 2;
        g.r = 2;
        // BS: [A U; B V].
        g.A = Mat{{theta, 0.0}, {-r3 / 3.0, theta}};
        g.U = Mat{{1.0, -u}, {1.0, u}};
        g.B = Mat{{0.5, 0.5}, {0.5, -0.5}};
        g.V = Mat{{1.0, 0.0}, {0.0, -1.0}};
        // c = A e (pre-consistency vector (1, 0), consistency vector q₁ = 0).
        g.c = Vec{{theta, theta - r3 / 3.0}};
        // BS: G = diag(1, 1 + 2√3/3), D = diag(½, ½).
        g.G = Mat{{1.0, 0.0}, {0.0, 1.0 + 2.0 * r3 / 3.0}};
        g.D = Mat{{0.5, 0.0}, {0.0, 0.5}};
        // BS starting method [A₀ U₀; B₀ V₀].
        g.s0 = 2;
        g.A0 = Mat{{theta, 0.0}, {-(3.0 + r3) / 3.0, theta}};
        g.U0 = Vec{{1.0, 1.0}};
        g.B0 = Mat{{0.0, 0.0}, {(r3 - 1.0) / 8.0, (1.0 - r3) / 8.0}};
        g.V0 = Vec{{1.0, 0.0}};
        g.c0 = Vec{{theta, theta - (3.0 + r3) / 3.0}};
        g.citation = "BS (Butcher 2006 slides: G-symplectic GLM, starting method, Theorem 3)";
        return g;
    }();
    return m;
}

} // namespace dampsym
