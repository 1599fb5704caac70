// An array handed to a plugin (plugin_kernel.hpp, docs/plugins.md): n doubles with `guard` cells on
// each side holding a sentinel, so that a write before element 0 or past element n-1 is seen after
// the call; and the payload preset to a signalling-NaN pattern so that an element the plugin did
// not write is seen too. Both are compared bit for bit: arithmetic never produces the pattern (a
// signalling NaN is quieted by every floating-point operation) and a plugin that copies its input
// cannot (the inputs are finite states or their host copies).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace dampsym {

class GuardedBuffer {
public:
    static constexpr std::size_t guard = 8;
    static constexpr std::uint64_t sentinel_bits = 0xFEF7D2F0C7F4E1A5ULL;  // a finite -1.7e303
    static constexpr std::uint64_t unwritten_bits = 0x7FF4DA5E5D00D1EDULL; // a signalling NaN

    // The guard cells are set here, once: a call that changes one is a fault that ends the run,
    // so they need no re-arming per call (rearm_guards() is there for a reused buffer).
    explicit GuardedBuffer(std::size_t n = 0) : n_(n), cells_(n + 2 * guard) { rearm_guards(); }

    double* data() { return cells_.data() + guard; }
    const double* data() const { return cells_.data() + guard; }
    std::size_t size() const { return n_; }

    // The payload to the unwritten pattern (the guards keep their sentinel).
    void arm_unwritten() {
        for (std::size_t i = 0; i < n_; ++i) put(guard + i, unwritten_bits);
    }
    // The payload a copy of z[0, n).
    void arm_copy(const double* z) {
        if (n_ > 0) std::memcpy(data(), z, sizeof(double) * n_);
    }
    void rearm_guards() {
        for (std::size_t i = 0; i < guard; ++i) {
            put(i, sentinel_bits);
            put(guard + n_ + i, sentinel_bits);
        }
    }
    // Whether both guard zones hold the sentinel (no allocation: checked after every call).
    bool guards_intact() const {
        for (std::size_t i = 0; i < guard; ++i)
            if (bits(i) != sentinel_bits || bits(guard + n_ + i) != sentinel_bits) return false;
        return true;
    }
    // "" if both guard zones are intact, else which one changed: "before NAME[0]" or
    // "past NAME[n)".
    std::string guard_fault(const std::string& name) const {
        for (std::size_t i = 0; i < guard; ++i)
            if (bits(i) != sentinel_bits) return "before " + name + "[0]";
        for (std::size_t i = 0; i < guard; ++i)
            if (bits(guard + n_ + i) != sentinel_bits)
                return "past " + name + "[" + std::to_string(n_) + ")";
        return "";
    }
    // The first payload element still holding the unwritten pattern, or -1.
    std::ptrdiff_t first_unwritten() const {
        for (std::size_t i = 0; i < n_; ++i)
            if (bits(guard + i) == unwritten_bits) return static_cast<std::ptrdiff_t>(i);
        return -1;
    }
    // Whether the payload equals z[0, n) bit for bit.
    bool payload_equals(const double* z) const {
        return n_ == 0 || std::memcmp(data(), z, sizeof(double) * n_) == 0;
    }

private:
    void put(std::size_t i, std::uint64_t b) { std::memcpy(&cells_[i], &b, sizeof b); }
    std::uint64_t bits(std::size_t i) const {
        std::uint64_t b;
        std::memcpy(&b, &cells_[i], sizeof b);
        return b;
    }

    std::size_t n_;
    std::vector<double> cells_;
};

} // namespace dampsym
