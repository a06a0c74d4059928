// The benchmark programs' timing: the fastest of three runs, in seconds (the least disturbed by
// the rest of the machine).
#pragma once

#include <algorithm>
#include <chrono>
#include <functional>

namespace sdp::bench {

inline double bestOfThreeSeconds(const std::function<void()>& run) {
  double best = 1e300;
  for (int k = 0; k < 3; ++k) {
    const auto start = std::chrono::steady_clock::now();
    run();
    best = std::min(
        best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

}  // namespace sdp::bench
