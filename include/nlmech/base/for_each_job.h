#pragma once
// Independent jobs of very different cost (strain-space samples, sweep points) on deal.II's task
// threads, each thread taking the next job when it is free.

#include <deal.II/base/multithread_info.h>
#include <deal.II/base/thread_management.h>

#include <algorithm>
#include <atomic>
#include <cstddef>

namespace nlmech
{
  /// Calls job(i) once for each i in [0, n) on up to n_threads() of deal.II's task threads
  /// (in index order on one thread). job must catch its own exceptions and guard what it shares;
  /// the element loops inside a job may use the task threads themselves.
  template <typename Job>
  void for_each_job(const std::size_t n, const Job &job)
  {
    const std::size_t workers = std::min<std::size_t>(n, dealii::MultithreadInfo::n_threads());
    if (workers <= 1)
      {
        for (std::size_t i = 0; i < n; ++i)
          job(i);
        return;
      }
    std::atomic<std::size_t> next{0};
    const auto               pull = [&]() {
      for (std::size_t i = next++; i < n; i = next++)
        job(i);
    };
    dealii::Threads::TaskGroup<void> tasks;
    for (std::size_t w = 0; w < workers; ++w)
      tasks += dealii::Threads::new_task(pull);
    tasks.join_all();
  }
} // namespace nlmech
