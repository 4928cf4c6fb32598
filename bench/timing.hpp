#pragma once
// What the benchmarks share: this thread's CPU time and a per-frame timing summary.

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <vector>

namespace gs::bench {

// CPU time of this thread: the machine may be shared, wall time then overstates the cost.
inline double thread_cpu_ms() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

// One line: mean, p50, p90, p99 and max of per-frame milliseconds, `what` padded to `width`.
inline void report(const char* what, std::vector<double> ms, int width = 10) {
    if (ms.empty()) return;
    std::sort(ms.begin(), ms.end());
    auto pct = [&](double p) {
        return ms[std::min(ms.size() - 1, std::size_t(p * double(ms.size())))];
    };
    double sum = 0;
    for (double v : ms) sum += v;
    std::printf("%-*s mean %6.2f ms  p50 %6.2f  p90 %6.2f  p99 %6.2f  max %6.2f  (%zu frames)\n",
                width, what, sum / double(ms.size()), pct(0.5), pct(0.9), pct(0.99), ms.back(),
                ms.size());
}

}  // namespace gs::bench
