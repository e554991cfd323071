#include <nlmech/base/threads.h>

#include <dlfcn.h>

namespace nlmech
{
  void serialise_openmp()
  {
    // Looked up at run time: the OpenMP runtime comes in through CHOLMOD (libgomp), not through
    // our own code, which is not compiled with OpenMP.
    static const bool done = [] {
      using SetLevels = void (*)(int);
      if (void *f = dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"))
        reinterpret_cast<SetLevels>(f)(0);
      return true;
    }();
    (void)done;
  }
} // namespace nlmech
