// Data-parallel loops for the core, on std::thread rather than OpenMP: under a memory limit
// OpenMP's runtime ends the whole process when it cannot start a thread (fatal for a MeshLab
// session), and an exception escaping an OpenMP loop terminates it. Here a thread that cannot be
// started leaves its share to the calling thread, and an exception in any share (e.g.
// std::bad_alloc) reaches the caller.
#pragma once

#include <algorithm>
#include <exception>
#include <new>
#include <system_error>
#include <thread>
#include <vector>

namespace sdp {

// Number of threads parallelFor uses at most (the machine's cores).
inline int parallelWorkers() {
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// Calls body(begin, end, worker) on disjoint contiguous ranges covering [0, n), each range at
// least `min_chunk` long (so small loops stay on one thread); worker < parallelWorkers().
template <class Body>
void parallelFor(int n, int min_chunk, Body&& body) {
  const int workers = std::clamp(n / std::max(min_chunk, 1), 1, parallelWorkers());
  if (workers == 1) {
    if (n > 0) body(0, n, 0);
    return;
  }
  std::vector<std::exception_ptr> errors(workers);
  auto share = [&](int w) {
    try {
      body(static_cast<int>(static_cast<long long>(n) * w / workers),
           static_cast<int>(static_cast<long long>(n) * (w + 1) / workers), w);
    } catch (...) {
      errors[w] = std::current_exception();
    }
  };
  std::vector<std::thread> threads;
  int started = 1;
  try {
    threads.reserve(workers - 1);
    for (; started < workers; ++started) threads.emplace_back(share, started);
  } catch (const std::system_error&) {  // no more threads: the rest runs here
  } catch (const std::bad_alloc&) {
  }
  share(0);
  for (int w = started; w < workers; ++w) share(w);
  for (auto& t : threads) t.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace sdp
