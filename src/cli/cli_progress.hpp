// The progress line of `dampsym run` on stderr (cli.cpp's cmd_run).
#pragma once

#include "harness/run/progress.hpp"

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <functional>
#include <iostream>
#include <mutex>
#include <thread>

namespace dampsym::cli_detail {

// The progress line on stderr: only when stderr is a terminal, and only once the run has taken
// more than a second; erased when the run ends. `on_case` (if set) is called with the record of
// each case as it finishes, one call at a time, with the progress line erased first, terminal or
// not (the per-case lines of `dampsym run`, so that a CI log shows each case when it ends).
class ProgressLine {
public:
    explicit ProgressLine(bool enabled,
                          std::function<void(const nlohmann::json&)> on_case = nullptr)
        : enabled_(enabled), on_case_(std::move(on_case)), start_(Clock::now()) {
        if (enabled_) thread_ = std::thread([this] { loop(); });
    }
    ~ProgressLine() { stop(); }
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    ProgressCallback callback() {
        if (!enabled_ && !on_case_) return {};
        return [this](const RunProgress& p) {
            std::lock_guard<std::mutex> lock(m_);
            state_ = p;
            state_.finished = nullptr; // valid only during this call
            if (!p.finished || !on_case_) return;
            if (shown_) std::cerr << "\r\033[K" << std::flush;
            shown_ = false;
            on_case_(*p.finished);
        };
    }
    void stop() {
        if (!thread_.joinable()) return;
        {
            std::lock_guard<std::mutex> lock(m_);
            done_ = true;
        }
        cv_.notify_all();
        thread_.join();
        if (shown_) std::cerr << "\r\033[K" << std::flush;
    }

private:
    using Clock = std::chrono::steady_clock;
    void loop() {
        std::unique_lock<std::mutex> lock(m_);
        while (!cv_.wait_for(lock, std::chrono::milliseconds(250), [this] { return done_; })) {
            const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
            if (elapsed < 1.0) continue;
            char eta[32] = "?";
            if (!state_.planned)
                std::snprintf(eta, sizeof eta, "? (references)");
            else if (state_.tasks_done > 0 && state_.tasks_total >= state_.tasks_done)
                std::snprintf(eta, sizeof eta, "%.0f s",
                              elapsed *
                                  static_cast<double>(state_.tasks_total - state_.tasks_done) /
                                  static_cast<double>(state_.tasks_done));
            char line[256];
            std::snprintf(line, sizeof line, "[%zu/%zu cases] %.40s  %.0f s elapsed, ETA %s",
                          state_.cases_done, state_.cases_total, state_.current.c_str(), elapsed,
                          eta);
            std::cerr << "\r\033[K" << line << std::flush;
            shown_ = true;
        }
    }
    bool enabled_;
    std::function<void(const nlohmann::json&)> on_case_;
    Clock::time_point start_;
    std::mutex m_;
    std::condition_variable cv_;
    RunProgress state_;
    bool done_ = false, shown_ = false;
    std::thread thread_;
};

} // namespace dampsym::cli_detail
