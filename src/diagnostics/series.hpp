// Time series for figures (docs/reports.md "Series files"). Used only when a run is made
// with --figures: nothing here is constructed, computed or stored otherwise, so the bare step loop
// and the lazy diagnostics of recorder.hpp are untouched.
//
// MinMaxDecimator keeps, of every bucket of consecutive samples, the sample with the smallest and
// the one with the largest value (in time order), so that a series of any length is reduced to at
// most 2 × buckets points and its extremes — the maxima the report states — are kept exactly.
// StrideSampler keeps every k-th sample (orbits: the shape, not the extremes, matters).
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace dampsym {

// Buckets per series: at most 2 × this many points per series in a series file.
inline constexpr std::int64_t kSeriesBuckets = 1000;
// At most this many points of a portrait (the attractor's probe plane, B Fig 5.10).
inline constexpr std::int64_t kPortraitPoints = 20000;
// Samples per orbit (StrideSampler): 100 per revolution over the 100 revolutions of the longest
// Kepler case (HLW Table 2.1), so that the drawn orbit is smooth, not a polygon.
inline constexpr std::int64_t kOrbitSamples = 10000;
// At most this many numbers per orbit (the outer solar system's 36-number states: 1111 samples).
inline constexpr std::int64_t kOrbitValues = 40000;
inline std::int64_t orbit_samples(std::int64_t dim) {
    return std::max<std::int64_t>(
        2, std::min(kOrbitSamples, kOrbitValues / std::max<std::int64_t>(1, dim)));
}

// A value as a figure draws it: rounded to 7 significant digits, so that it is written as at most
// 7 digits in a series file (orbits are drawn, not compared with the report; a third the size).
// (to_chars as printf's "%.7g", from_chars as strtod: both correctly rounded, several times
// faster.)
inline double drawn_value(double x) {
    if (!std::isfinite(x)) return x;
    char buf[32];
    const auto end = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, 7).ptr;
    double y = x;
    std::from_chars(buf, end, y);
    return y;
}

class MinMaxDecimator {
public:
    // total: the number of samples that will be pushed (sets the bucket size).
    explicit MinMaxDecimator(std::int64_t total, std::int64_t buckets = kSeriesBuckets)
        : per_(std::max<std::int64_t>(1, (total + buckets - 1) /
                                             std::max<std::int64_t>(1, buckets))) {}

    // Non-finite values are counted (nonfinite()) and skipped: a series never carries NaN.
    void push(double t, double y) {
        last_t_ = t, last_y_ = y;
        if (!std::isfinite(y)) {
            ++nonfinite_;
        } else {
            if (!have_ || y < lo_y_) lo_t_ = t, lo_y_ = y;
            if (!have_ || y > hi_y_) hi_t_ = t, hi_y_ = y;
            have_ = true;
        }
        if (++in_bucket_ == per_) flush();
    }
    void flush() {
        if (have_) {
            if (lo_t_ < hi_t_) {
                emit(lo_t_, lo_y_);
                emit(hi_t_, hi_y_);
            } else if (hi_t_ < lo_t_) {
                emit(hi_t_, hi_y_);
                emit(lo_t_, lo_y_);
            } else {
                emit(lo_t_, lo_y_);
            }
        }
        have_ = false;
        in_bucket_ = 0;
    }
    const std::vector<double>& t() const { return t_; }
    const std::vector<double>& y() const { return y_; }
    std::int64_t nonfinite() const { return nonfinite_; }
    std::int64_t samples_per_bucket() const { return per_; }

    // {"t": [...], "y": [...], "per_bucket": k, "nonfinite": m, "last": [t, y]} (flushes the
    // open bucket).
    nlohmann::json to_json() {
        flush();
        nlohmann::json out = {
            {"t", t_}, {"y", y_}, {"per_bucket", per_}, {"nonfinite", nonfinite_}};
        // the last sample as pushed (a final value), null if none or not finite
        out["last"] = std::isfinite(last_y_) ? nlohmann::json{last_t_, last_y_} : nlohmann::json();
        return out;
    }

private:
    void emit(double t, double y) {
        t_.push_back(t);
        y_.push_back(y);
    }
    std::int64_t per_, in_bucket_ = 0, nonfinite_ = 0;
    bool have_ = false;
    double lo_t_ = 0, lo_y_ = 0, hi_t_ = 0, hi_y_ = 0;
    double last_t_ = 0, last_y_ = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> t_, y_;
};

// Every k-th of `total` samples (k = ceil(total / samples)), plus the last one.
class StrideSampler {
public:
    explicit StrideSampler(std::int64_t total, std::int64_t samples = kOrbitSamples)
        : per_(std::max<std::int64_t>(1,
                                      (total + samples - 1) / std::max<std::int64_t>(1, samples))),
          total_(total) {}
    bool wants(std::int64_t i) const { return i % per_ == 0 || i == total_ - 1; }
    std::int64_t stride() const { return per_; }

private:
    std::int64_t per_, total_;
};

} // namespace dampsym
