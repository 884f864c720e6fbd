// A minimal parallel loop for independent work items (grid points, chunks of samples).
#pragma once

#ifdef __linux__
#include <sched.h>
#endif

#include <algorithm>
#include <thread>
#include <vector>

namespace brdffit {

// The cores this process may run on: its CPU affinity, which a scheduler's cpuset (Slurm, a
// container's limit, taskset, mpirun's binding) narrows; every core of the machine otherwise.
inline int available_cores() {
#ifdef __linux__
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof(allowed), &allowed) == 0 && CPU_COUNT(&allowed) > 0) return CPU_COUNT(&allowed);
#endif
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// The number of worker threads to use for a request of `requested` (0: every available core).
inline int thread_count(int requested) { return requested > 0 ? requested : available_cores(); }

// Calls body(i) for i in [0, n) on up to `threads` threads; items are interleaved so that
// uneven items spread across threads. body must not throw.
template <class Body>
void parallel_for(size_t n, int threads, Body&& body) {
  const size_t workers = std::min<size_t>(n, static_cast<size_t>(std::max(1, threads)));
  if (workers <= 1) {
    for (size_t i = 0; i < n; ++i) body(i);
    return;
  }
  std::vector<std::thread> pool;
  for (size_t w = 0; w < workers; ++w)
    pool.emplace_back([&, w] {
      for (size_t i = w; i < n; i += workers) body(i);
    });
  for (std::thread& t : pool) t.join();
}

// Splits [0, count) into `chunks` contiguous ranges and calls body(begin, end, chunk) for each
// on up to `threads` threads: the loop over samples of the fitter's cost and of the metrics,
// each chunk summing into its own slot so the total does not depend on the thread count.
template <class Body>
void parallel_chunks(size_t count, size_t chunks, int threads, Body&& body) {
  const size_t per_chunk = (count + chunks - 1) / std::max<size_t>(chunks, 1);
  parallel_for(chunks, threads, [&](size_t chunk) {
    const size_t begin = std::min(count, chunk * per_chunk);
    body(begin, std::min(count, begin + per_chunk), chunk);
  });
}

}  // namespace brdffit
