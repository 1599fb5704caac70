// Exact solution of the perturbed rigid body B(1.7) (conventions §2, B §3.4):
//
//   z' = z × (I⁻¹ z) − γ(t) z,   γ(t) = ½ε cos 2t,   Γ(t) = ¼ε sin 2t,   z(0) = z0
// (written here for a start at t = 0; rigid_body_exact below starts at any t0).
//
// N(z) = z × (I⁻¹ z) is homogeneous of degree 2, so with τ(t) = ∫₀ᵗ e^{−Γ(s)} ds
//
//   z(t) = e^{−Γ(t)} y(τ(t)),   y' = y × (I⁻¹ y),  y(0) = z0     (the free rigid body)
//
// (z' = −γz + e^{−2Γ} N(y(τ)) = −γz + N(z)). The free body is solved in closed form:
//
// * z0 with at most one non-zero component (a principal axis, or 0), or I1 = I2 = I3: y ≡ z0.
// * Symmetric top (exactly two equal moments, the third axis l, (i, j, l) cyclic, a = 1/I_i =
//   1/I_j): y_l is constant and (y_i, y_j) rotates with Ω = (1/I_l − a) y_l:
//   y_i = y_i0 cos Ωs + y_j0 sin Ωs,  y_j = y_j0 cos Ωs − y_i0 sin Ωs.
// * Distinct moments: Jacobi elliptic functions. Let a_i = 1/I_i, sorted a_lo < a_mid < a_hi,
//   δ = (a_hi − a_mid) y_hi² − (a_mid − a_lo) y_lo² = 2H − a_mid C (C = |y|², 2H = Σ a_i y_i²),
//   the side of the separatrix. A signed permutation w = R P y (R P ∈ SO(3) up to the sign s
//   below) maps the problem to w' = w × (B w), B = diag(b1 < b2 < b3), with the never-vanishing
//   component in position 3:
//     δ ≥ 0 (rotation about the axis of smallest moment):  w = (y_lo, y_mid, y_hi), b = +a, s = +1
//     δ < 0 (rotation about the axis of largest moment):   w = (y_hi, y_mid, y_lo), b = −a, s = −1
//   (for a signed permutation Q, Q(u × v) = det(Q) (Qu × Qv), so w' = det(Q) w × (B_Q w); Q's
//   sign flips (negating w2 when det P ≠ s) make det Q = s, and s·a_P is increasing). With
//   d21 = b2 − b1, d32 = b3 − b2, d31 = b3 − b1 (all > 0, formed as differences of 1/I without
//   cancellation) and the cancellation-free
//     A1 = d31 w1² + d32 w2² (= b3 C − 2H),   A3 = d21 w2² + d31 w3² (= 2H − b1 C),
//   eliminating w1², w3² through C and H gives (w2')² = A1 A3 (1 − w2²/β1)(1 − w2²/β3) with
//   β1 = A1/d32, β3 = A3/d21, hence, with m = k² = β1/β3 = d21 A1/(d32 A3) ≤ 1,
//     1 − m = d31 δ_b/(d32 A3),  δ_b = d32 w3² − d21 w1² ≥ 0,   λ = √(d32 A3),
//     w1 = σ1 √α1 cn(u|m),  w2 = −σ1σ3 √β1 sn(u|m),  w3 = σ3 √α3 dn(u|m),  u = λ s + u0,
//   α1 = A1/d31, α3 = A3/d31, σ1 = sign w1(0) (+1 for 0), σ3 = sign w3(0) (≠ 0 off the axes).
//   (Each of the three Euler equations checks by squaring; the sign of w2 fixes the direction.)
//   The phase: cn(u0) = |w1(0)|/√α1 ≥ 0 and sn(u0) = −σ1σ3 w2(0)/√β1, so am(u0) = φ0 ∈
//   [−π/2, π/2] and u0 = F(φ0|m) = sin φ0 · R_F(cos²φ0, cos²φ0 + (1−m) sin²φ0, 1) (Carlson),
//   finite also on the separatrix m = 1 (where sn = tanh, cn = dn = sech, and cn(u0) > 0 holds
//   because σ1 = sign w1(0)). u is reduced modulo 4K(m) = 4 R_F(0, 1−m, 1); sn, cn, dn come from
//   gsl_sf_elljac_e, after descending Landen steps when 1 − m < ½ (GSL forms √(1−m) from m, which
//   near the separatrix would cost the relative accuracy of 1 − m and of dn ≈ √(1−m)).
//   Everything is analytic: there is no numerical fallback (the unstable middle-axis
//   equilibrium is the "at most one non-zero component" case).
//
// τ(t): e^{−Γ} has period π; τ(nπ + r) = n τ(π) + τ(r), r ∈ [0, π) (r by a two-part π), each part
// by 20-point Gauss–Legendre on subintervals of length π/(8⌈max(1, |ε|/4)⌉). τ(π) = π I0(ε/4).
//
// GSL's error handler is switched off once (std::call_once); a failing GSL call gives NaN
// components, never an abort or an exception.
#pragma once

#include <array>

namespace dampsym {

using Vec3 = std::array<double, 3>;

// The free rigid body y' = y × (I⁻¹ y), y(0) = y0, in closed form (see above). I_i > 0.
class FreeRigidBody {
public:
    enum class Kind { constant, symmetric, elliptic };

    FreeRigidBody(const Vec3& inertia, const Vec3& y0);

    Vec3 at(double s) const; // y(s)

    Kind kind() const { return kind_; }
    double m() const { return m_; }   // elliptic parameter k² (elliptic case)
    double m1() const { return m1_; } // 1 − k², computed without cancellation
    double lambda() const { return lambda_; }
    double u0() const { return u0_; }
    bool ok() const { return ok_; } // false if a GSL call failed during setup

private:
    Kind kind_ = Kind::constant;
    Vec3 y0_{};
    bool ok_ = true;
    // symmetric top
    int i_ = 0, j_ = 1, l_ = 2;
    double omega_ = 0.0;
    // elliptic: y[perm_[k]] = sign_[k] * w_k
    std::array<int, 3> perm_{0, 1, 2};
    std::array<double, 3> sign_{1.0, 1.0, 1.0};
    double c1_ = 0.0, c2_ = 0.0, c3_ = 0.0; // w1 = c1 cn, w2 = c2 sn, w3 = c3 dn
    double m_ = 0.0, m1_ = 1.0, lambda_ = 0.0, u0_ = 0.0, four_k_ = 0.0;
};

// τ(t) = ∫₀ᵗ e^{−Γ(s)} ds with Γ(s) = ¼ε sin 2s (any real t).
double rigid_body_tau(double epsilon, double t);

// z(t) of B(1.7) with γ(t) = ½ε cos 2t and z(t0) = z0, any t0 (B(1.7) is not autonomous, so
// this is not a shift of the solution from t = 0):
//   z(t) = e^{−(Γ(t) − Γ(t0))} y(τ_{t0}(t)),   τ_{t0}(t) = ∫_{t0}^t e^{−(Γ(s) − Γ(t0))} ds
//        = e^{Γ(t0)} (τ(t) − τ(t0)),           y the free body with y(0) = z0.
// (z' = −γz + e^{−2(Γ(t)−Γ(t0))} N(y(τ_{t0})) = −γz + N(z).) t = t0 returns z0 exactly; at t0 = 0
// the formulas reduce bitwise to e^{−Γ(t)} y(τ(t)) (Γ(0) = 0, τ(0) = 0).
Vec3 rigid_body_exact(const Vec3& inertia, const Vec3& z0, double epsilon, double t0, double t);

} // namespace dampsym
