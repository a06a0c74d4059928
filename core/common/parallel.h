// Data-parallel loops for the core, on std::thread rather than OpenMP: under a memory limit
// OpenMP's runtime ends the whole process when it cannot start a thread (fatal for a MeshLab
// session), and an exception escaping an OpenMP loop terminates it. Here a thread that cannot be
// started leaves its share to the calling thread, and an exception in any share (e.g.
// std::bad_alloc) reaches the caller.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <new>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace sdp {

// Number of threads parallelFor uses at most (the machine's cores). Asked once: glibc reads
// /sys for it on every call, which was 5% of a small CAD part's atlas (a loop per chart).
inline int parallelWorkers() {
  static const int workers = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return workers;
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

// The slots of a pass over `n` faces whose per-slot sums are added in order: one per 16384, so
// each is long enough to share out and the count depends on the mesh alone.
inline int faceSumSlots(int n) {
  return std::max(1, n / 16384);
}

// Calls body(begin, end, slot) for `slots` contiguous ranges covering [0, n), shared out between
// the workers. The ranges depend on n and `slots` alone, never on the number of cores: partial
// sums kept per slot and added in slot order give the same bits on any machine.
template <class Body>
void parallelForSlots(int n, int slots, Body&& body) {
  slots = std::max(slots, 1);
  parallelFor(slots, 1, [&](int first, int last, int) {
    for (int s = first; s < last; ++s)
      body(static_cast<int>(static_cast<long long>(n) * s / slots),
           static_cast<int>(static_cast<long long>(n) * (s + 1) / slots), s);
  });
}

// Runs `task` on the calling thread while the other workers take chunks of [0, n) from a shared
// counter (body(begin, end, worker) as above); the calling thread joins in on the chunks once
// its task is done. For two independent stages of unequal length (the boundary alongside the
// weights): neither core waits for the other. An exception in the task or a chunk stops the
// handing out of chunks and reaches the caller. `most_workers` > 0 caps the threads (for loops
// whose workers each hold scratch the size of the mesh).
template <class Task, class Body>
void parallelForAlongside(int n, int chunk, Task&& task, Body&& body, int most_workers = 0) {
  const int workers =
      most_workers > 0 ? std::min(most_workers, parallelWorkers()) : parallelWorkers();
  chunk = std::max(chunk, 1);
  std::atomic<int> next{0};
  std::vector<std::exception_ptr> errors(workers);
  auto takeChunks = [&](int worker) {
    try {
      for (int begin = next.fetch_add(chunk); begin < n; begin = next.fetch_add(chunk))
        body(begin, std::min(n, begin + chunk), worker);
    } catch (...) {
      errors[worker] = std::current_exception();
      next.store(n);
    }
  };
  std::vector<std::thread> threads;
  try {
    threads.reserve(workers - 1);
    for (int w = 1; w < workers; ++w) threads.emplace_back(takeChunks, w);
  } catch (const std::system_error&) {  // fewer threads: the calling thread does the rest
  } catch (const std::bad_alloc&) {
  }
  try {
    task();
  } catch (...) {
    errors[0] = std::current_exception();
    next.store(n);
  }
  if (!errors[0]) takeChunks(0);
  for (auto& t : threads) t.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

// Calls body(begin, end, worker) on chunks of [0, n) handed out one at a time from a shared
// counter: for items of unequal cost (charts, bands of a texture), where fixed shares would leave
// one core waiting on the other's long share.
template <class Body>
void parallelForDynamic(int n, int chunk, Body&& body, int most_workers = 0) {
  parallelForAlongside(
      n, chunk, [] {}, std::forward<Body>(body), most_workers);
}

// Sorts `items` as std::sort does when no two compare equal (distinct keys have one order):
// from `min_items` on, two halves at once, then merged.
template <class T>
void sortOnTwoCores(std::vector<T>& items, size_t min_items = 65536) {
  if (items.size() < min_items) {
    std::sort(items.begin(), items.end());
    return;
  }
  const auto middle = items.begin() + static_cast<std::ptrdiff_t>(items.size() / 2);
  parallelFor(2, 1, [&](int first, int last, int) {
    for (int h = first; h < last; ++h)
      std::sort(h == 0 ? items.begin() : middle, h == 0 ? middle : items.end());
  });
  std::inplace_merge(items.begin(), middle, items.end());
}

// The lists kept per slot of a parallel pass, joined in slot order (so the same on any number
// of cores) and freed.
template <class T>
std::vector<T> joinedInOrder(std::vector<std::vector<T>>& lists) {
  size_t total = 0;
  for (const std::vector<T>& list : lists) total += list.size();
  std::vector<T> joined;
  joined.reserve(total);
  for (std::vector<T>& list : lists) {
    joined.insert(joined.end(), list.begin(), list.end());
    list = std::vector<T>();
  }
  return joined;
}

// Places items [0, n) in buckets [0, buckets), each bucket's items in item order, and returns the
// buckets' begins (buckets + 1 of them): a counting sort in slots of consecutive items, one per
// core (a few at most: each holds a count per bucket), filled in slot order, so the placement is
// the same on any number of cores. forEach(begin, end, emit) calls emit(bucket, item) for the
// items of [begin, end) that go somewhere (none, one or several each); it runs twice, to count
// and to place. size(total) is called once the items placed are counted, then
// place(position, item) for each.
template <class ForEach, class Size, class Place>
std::vector<int> bucketsInOrder(int n, int buckets, ForEach&& forEach, Size&& size, Place&& place) {
  const int slots = std::clamp(n / 16384, 1, std::min(parallelWorkers(), 4));
  std::vector<std::vector<int>> next(slots);  // per slot and bucket: where its next item goes
  parallelForSlots(n, slots, [&](int begin, int end, int slot) {
    std::vector<int>& count = next[slot];
    count.assign(buckets, 0);
    forEach(begin, end, [&](int bucket, int) { ++count[bucket]; });
  });
  std::vector<int> bucket_begin(buckets + 1, 0);
  for (int b = 0; b < buckets; ++b) {
    int total = 0;
    for (int s = 0; s < slots; ++s) total += next[s][b];
    bucket_begin[b + 1] = bucket_begin[b] + total;
  }
  parallelFor(buckets, 16384, [&](int first, int last, int) {
    for (int b = first; b < last; ++b) {
      int position = bucket_begin[b];
      for (int s = 0; s < slots; ++s) {
        const int count = next[s][b];
        next[s][b] = position;
        position += count;
      }
    }
  });
  size(bucket_begin[buckets]);
  parallelForSlots(n, slots, [&](int begin, int end, int slot) {
    std::vector<int>& position = next[slot];
    forEach(begin, end, [&](int bucket, int item) { place(position[bucket]++, item); });
  });
  return bucket_begin;
}

}  // namespace sdp
