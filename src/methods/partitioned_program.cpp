// The partitioned engine's schedule and program (partitioned_program.hpp).
#include "methods/partitioned_program.hpp"

namespace dampsym {

namespace {
std::size_t program_index(int i) {
    return static_cast<std::size_t>(i);
}
} // namespace

void PartitionedProgram::build(const ExponentialTableau& hat, const ExponentialTableau& tilde) {
    need_force.clear();
    for (int j = 0; j < s_; ++j) {
        bool force_used = tilde.b[j] != 0.0;
        for (int i = 0; i < s_; ++i) force_used = force_used || tilde.A(i, j) != 0.0;
        need_force.push_back(force_used);
    }
    std::vector<bool> qd(program_index(s_), false), pd(program_index(s_), false);
    std::vector<int> order;
    bool progress = true;
    while (progress && static_cast<int>(order.size()) < 2 * s_) {
        progress = false;
        for (int i = 0; i < s_; ++i) {
            if (!qd[program_index(i)]) {
                bool ready = true;
                for (int j = 0; j < s_; ++j)
                    if (hat.A(i, j) != 0.0 && !pd[program_index(j)]) ready = false;
                if (ready) {
                    qd[program_index(i)] = true;
                    order.push_back(i);
                    progress = true;
                }
            }
            if (!pd[program_index(i)]) {
                bool ready = true;
                for (int j = 0; j < s_; ++j)
                    if (tilde.A(i, j) != 0.0 &&
                        (!qd[program_index(j)] || (damped_ && j != i && !pd[program_index(j)])))
                        ready = false;
                if (ready) {
                    pd[program_index(i)] = true;
                    order.push_back(s_ + i);
                    progress = true;
                }
            }
        }
    }
    schedule.clear();
    if (static_cast<int>(order.size()) == 2 * s_) schedule = order;
}

void PartitionedProgram::compile(const ExponentialTableau& hat, const ExponentialTableau& tilde,
                                 double h) {
    program.clear();
    terms.clear();
    for (const int code : schedule) {
        Task task{code < s_ ? code : code - s_, code < s_, false, 0.0, 0.0, terms.size(), 0};
        const int i = task.i;
        if (task.q) {
            task.force = need_force[program_index(i)] != 0;
            task.phi = hat.phi[i];
            for (int j = 0; j < s_; ++j)
                if (hat.A(i, j) != 0.0) terms.push_back({j, h * hat.A(i, j), 0.0});
        } else {
            task.phi = tilde.phi[i];
            task.damping_ii = 2.0 * h * tilde.A(i, i);
            for (int j = 0; j < s_; ++j) {
                const double a = tilde.A(i, j);
                if (a != 0.0) terms.push_back({j, h * a, 2.0 * h * a});
            }
        }
        task.last = terms.size();
        program.push_back(task);
    }
    bq.clear();
    bp.clear();
    for (int i = 0; i < s_; ++i) {
        if (hat.b[i] != 0.0) bq.push_back({i, damped_ ? h * hat.b[i] : hat.b[i]});
        if (tilde.b[i] != 0.0) bp.push_back({i, h * tilde.b[i]});
    }
}

partitioned_shapes::Shape PartitionedProgram::shape(const ExponentialTableau& hat,
                                                    const ExponentialTableau& tilde) const {
    using partitioned_shapes::kStages;
    partitioned_shapes::Shape sh;
    if (!scheduled() || s_ > kStages) return sh;
    sh.rayleigh = damped_;
    sh.s = s_;
    for (std::size_t k = 0; k < schedule.size(); ++k) sh.order[k] = schedule[k];
    for (const Task& task : program) {
        const int i = task.i;
        if (task.q && task.force) sh.force |= 1u << i;
        if (task.phi == 1.0) (task.q ? sh.unit_q : sh.unit_p) |= 1u << i;
        for (std::size_t k = task.first; k < task.last; ++k)
            (task.q ? sh.q_terms : sh.p_terms) |= partitioned_shapes::pair_bit(i, terms[k].j);
    }
    for (const Weight& b : bq) {
        sh.bq |= 1u << b.i;
        if (!damped_ && b.w == 1.0) sh.unit_bq |= 1u << b.i;
    }
    for (const Weight& b : bp) sh.bp |= 1u << b.i;
    if (hat.phi0 == 1.0) sh.unit_q |= 1u << kStages;
    if (tilde.phi0 == 1.0) sh.unit_p |= 1u << kStages;
    return sh;
}

int PartitionedProgram::compile_shape(const ExponentialTableau& hat,
                                      const ExponentialTableau& tilde,
                                      partitioned_shapes::Coefficients& fc) const {
    const auto& shapes = partitioned_shapes::kShapes;
    const partitioned_shapes::Shape sh = shape(hat, tilde);
    int found = 0;
    for (std::size_t k = 0; k < shapes.size() && found == 0; ++k)
        if (sh.s != 0 && partitioned_shapes::compiles(shapes[k], sh))
            found = static_cast<int>(k) + 1;
    if (found == 0) return 0;
    fc = partitioned_shapes::Coefficients{};
    for (const Task& task : program) {
        const int i = task.i;
        (task.q ? fc.phi_q : fc.phi_p)[i] = task.phi;
        if (!task.q) fc.damping_ii[i] = task.damping_ii;
        for (std::size_t k = task.first; k < task.last; ++k) {
            const Term& term = terms[k];
            (task.q ? fc.q : fc.p)[i][term.j] = term.coef;
            if (!task.q) fc.damping[i][term.j] = term.damping;
        }
    }
    for (const Weight& b : bq) fc.bq[b.i] = b.w;
    for (const Weight& b : bp) fc.bp[b.i] = b.w;
    return found;
}

} // namespace dampsym
