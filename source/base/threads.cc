#include <nlmech/base/serial_blas.h>
#include <nlmech/base/threads.h>

#include <dlfcn.h>

namespace nlmech
{
  void serialise_openmp()
  {
    // Looked up at run time: the OpenMP runtime comes in through CHOLMOD (libgomp), not through
    // our own code, which is not compiled with OpenMP. libgomp keeps max-active-levels per thread
    // (a thread it has not seen starts from the default), so every thread that may call CHOLMOD
    // sets it once: on deal.II's task threads, CHOLMOD otherwise opened teams of 4 again, and the
    // DIM samples solved on two threads differed in the last digits from one run to the next.
    thread_local const bool done = [] {
      using SetLevels = void (*)(int);
      if (void *f = dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"))
        reinterpret_cast<SetLevels>(f)(0);
      return true;
    }();
    (void)done;
  }

  std::unique_lock<std::mutex> lock_serial_blas()
  {
    static std::mutex blas;
    return std::unique_lock<std::mutex>(blas);
  }
} // namespace nlmech
