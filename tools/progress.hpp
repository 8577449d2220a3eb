// tools/progress.hpp — a progress bar on stderr for renders longer than ~1 s.
//
// Debian ships no C++ progress-bar library; this is the few lines needed.
// tick() may be called from any thread; only one thread draws at a time and
// nothing is drawn before `delay` has passed, so short renders stay silent.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace octray {

class Progress {
public:
    Progress(std::string label, long total, std::chrono::milliseconds delay = std::chrono::milliseconds(1000))
        : label_(std::move(label)), total_(total), delay_(delay), start_(Clock::now()) {}
    ~Progress() { finish(); }

    void tick(long n = 1) {
        const long done = done_.fetch_add(n) + n;
        const auto now = Clock::now();
        if (now - start_ < delay_) return;
        std::unique_lock<std::mutex> lock(draw_, std::try_to_lock);
        if (!lock.owns_lock() || now - last_ < std::chrono::milliseconds(100)) return;
        last_ = now;
        draw(done);
    }
    void finish() {
        if (drawn_) {
            draw(done_.load());
            std::fputc('\n', stderr);
            drawn_ = false;
        }
    }

private:
    using Clock = std::chrono::steady_clock;
    void draw(long done) {
        constexpr int kWidth = 40;
        const double f = total_ > 0 ? double(done) / double(total_) : 1.0;
        const int filled = int(f * kWidth);
        std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%", label_.c_str(), filled, "########################################",
                     kWidth - filled, "", int(f * 100));
        std::fflush(stderr);
        drawn_ = true;
    }
    std::string label_;
    long total_;
    std::chrono::milliseconds delay_;
    Clock::time_point start_, last_{};
    std::atomic<long> done_{0};
    std::mutex draw_;
    bool drawn_ = false;
};

}  // namespace octray
