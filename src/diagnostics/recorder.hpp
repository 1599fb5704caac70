// The observer attached to the step loop when a case asks for trajectory diagnostics: the states
// on the output grid (error, energy, ...) when a diagnostic reads them, and the per-step parts of
// the case's diagnostics (observer_part.hpp: each diagnostic of the list that declares a
// `Part<P>` has one optional slot here, enabled by the typed case when the case names it; no list
// of parts is written here). Everything is streamed; nothing grows with the number of steps except
// the requested grid, and not even that when the grid's only readers reduce it on the fly (a
// GridSink: harness/run/grid_stream.hpp).
#pragma once

#include "core/types.hpp"
#include "diagnostics/diagnostic_list.hpp"
#include "diagnostics/observer_part.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <tuple>
#include <type_traits>
#include <utility>

namespace dampsym {

// A reader of the output grid that reduces it on the fly (harness/run/grid_stream.hpp): given each
// grid point i >= 1 (the state at step i × stride) as the run reaches it, instead of a stored grid.
class GridSink {
public:
    virtual void point(Eigen::Index i, const Vec& z) = 0;

protected:
    ~GridSink() = default;
};

namespace detail {

// std::tuple<std::optional<D::Part<P>>...> over the diagnostics D of `List` with a part for P.
template <class P, class D, bool = has_observer_part<D, P>()>
struct PartSlot {
    using type = std::tuple<>;
};
template <class P, class D>
struct PartSlot<P, D, true> {
    using type = std::tuple<std::optional<typename D::template Part<P>>>;
};
template <class P, class List>
struct PartSlots;
template <class P, class... Ds>
struct PartSlots<P, TypeList<Ds...>> {
    using type = decltype(std::tuple_cat(std::declval<typename PartSlot<P, Ds>::type>()...));
};

} // namespace detail

template <class P>
class Recorder {
    using Slots = typename detail::PartSlots<P, DiagnosticList>::type;
    template <class D>
    using Slot = std::optional<typename D::template Part<P>>;

public:
    Recorder(const P& problem, double t0, double h) : p_(problem), t0_(t0), h_(h) {}

    void record_grid(std::int64_t stride, std::int64_t points) {
        stride_ = stride;
        grid_.resize(p_.dim(), points);
    }
    // Grid points i >= 1 to `sink` (not stored; the sink must outlive the run).
    void stream_grid(std::int64_t stride, GridSink* sink) {
        sink_stride_ = stride;
        sink_ = sink;
    }
    // Enables the per-step part of diagnostic D (a no-op for a diagnostic without one for P).
    template <class D>
    void enable(const PartContext& ctx) {
        if constexpr (has_observer_part<D, P>()) {
            static_assert(ObserverPart<typename D::template Part<P>>);
            std::get<Slot<D>>(parts_).emplace(p_, ctx);
        }
    }
    // The part of diagnostic D; only for an enabled one (its producer runs only then).
    template <class D>
    const typename D::template Part<P>& part() const {
        return *std::get<Slot<D>>(parts_);
    }
    template <class D>
    bool enabled() const {
        if constexpr (has_observer_part<D, P>())
            return std::get<Slot<D>>(parts_).has_value();
        else
            return false;
    }

    void start(const Vec& z0) {
        if (stride_ > 0) grid_.col(0) = z0;
        std::apply([&](auto&... s) { ((s ? s->start(z0) : void()), ...); }, parts_);
    }

    void operator()(std::int64_t n, double t, const Vec& z) {
        if (stride_ > 0 && n % stride_ == 0) grid_.col(n / stride_) = z;
        if (sink_ && n % sink_stride_ == 0) sink_->point(n / sink_stride_, z);
        std::apply([&](auto&... s) { ((s ? (*s)(n, t, z) : void()), ...); }, parts_);
    }

    // The per-step series of the enabled parts (those enabled with a series, PartContext).
    void series(nlohmann::json& out) {
        std::apply([&](auto&... s) { ((s ? s->series(out) : void()), ...); }, parts_);
    }

    const Mat& grid() const { return grid_; }
    double t0() const { return t0_; }
    double h() const { return h_; }

private:
    const P& p_;
    double t0_, h_;
    std::int64_t stride_ = 0;
    Mat grid_;
    std::int64_t sink_stride_ = 0;
    GridSink* sink_ = nullptr;
    Slots parts_;
};

} // namespace dampsym
