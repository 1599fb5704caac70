// The schedule and the compiled program of the partitioned engine (partitioned_engine.hpp). They
// depend on the coefficients only, not on the problem, so they are ordinary code compiled once
// (partitioned_program.cpp).
//
// Schedule: a greedy order of the tasks Q_i (code i: Q_i and its force) and P_i (code s + i) in
// which every Q_i needs only P stages already known and every P_i only forces already known (and,
// with the damping in the vector field, δ = 1, P_j (j ≠ i) already known), found from the
// structurally non-zero coefficients; empty when no order exists (the engine then solves the
// stages by Newton).
//
// Program: the scheduled step as a flat list over the structurally non-zero coefficients, with the
// products of h that the stage formulas form computed once (the same products in the same order,
// so the same values): no loop over zero coefficients and no test per step. Recompiled when the
// provider changes the coefficients. Its shape (partitioned_shapes.hpp) says whether the engine
// also has it as straight-line code.
#pragma once

#include "methods/exponential_tableaux.hpp"
#include "methods/partitioned_shapes.hpp"

#include <cstddef>
#include <vector>

namespace dampsym {

class PartitionedProgram {
public:
    struct Term {
        int j;
        double coef;    // h â_ij (Q task) or h ã_ij (P task)
        double damping; // 2h ã_ij (P task, δ = 1, j ≠ i): times γ_j
    };
    struct Task {
        int i;
        bool q, force;
        double phi;        // φ̂_i or φ̃_i
        double damping_ii; // 2h ã_ii (P task): the denominator is 1 + 2h ã_ii γ_i
        std::size_t first, last;
    };
    struct Weight {
        int i;
        double w; // h b̂_i (δ = 1) or b̂_i (δ = 0); h b̃_i
    };

    PartitionedProgram(int stages, bool rayleigh_damping) : s_(stages), damped_(rayleigh_damping) {}

    // Which forces are used (a column of Ã or b̃ not zero) and the schedule, from the structure.
    void build(const ExponentialTableau& hat, const ExponentialTableau& tilde);
    bool scheduled() const { return !schedule.empty(); }
    // The program for step h from the current coefficients (nothing when not scheduled).
    void compile(const ExponentialTableau& hat, const ExponentialTableau& tilde, double h);
    // The program's shape (s = 0 when not scheduled or more than kStages stages).
    partitioned_shapes::Shape shape(const ExponentialTableau& hat,
                                    const ExponentialTableau& tilde) const;
    // 1 + the index in kShapes of the first compiled shape that runs this program, with its
    // coefficient values in fc; 0 when none does.
    int compile_shape(const ExponentialTableau& hat, const ExponentialTableau& tilde,
                      partitioned_shapes::Coefficients& fc) const;

    std::vector<char> need_force;
    std::vector<int> schedule;
    std::vector<Task> program;
    std::vector<Term> terms;
    std::vector<Weight> bq, bp;

private:
    int s_;
    bool damped_;
};

} // namespace dampsym
