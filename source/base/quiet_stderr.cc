// Standard error silenced for a scope (quiet_stderr.h).
#include <nlmech/base/quiet_stderr.h>

#include <cstdio>
#include <cstdlib>
#include <mutex>

#include <fcntl.h>
#include <unistd.h>

namespace nlmech
{
  namespace
  {
    std::mutex   lock;
    unsigned int users = 0;
    int          saved = -1;
  } // namespace

  QuietStderr::QuietStderr()
  {
    // NLMECH_VERBOSE_SOLVERS keeps the libraries' own messages (for debugging a solve).
    static const bool verbose = std::getenv("NLMECH_VERBOSE_SOLVERS") != nullptr;
    if (verbose)
      return;
    const std::lock_guard<std::mutex> guard(lock);
    if (users++ > 0)
      return;
    std::fflush(stderr);
    saved          = dup(2);
    const int null = open("/dev/null", O_WRONLY);
    if (saved >= 0 && null >= 0)
      dup2(null, 2);
    if (null >= 0)
      close(null);
  }

  QuietStderr::~QuietStderr()
  {
    static const bool verbose = std::getenv("NLMECH_VERBOSE_SOLVERS") != nullptr;
    if (verbose)
      return;
    const std::lock_guard<std::mutex> guard(lock);
    if (--users > 0)
      return;
    std::fflush(stderr);
    if (saved >= 0)
      {
        dup2(saved, 2);
        close(saved);
        saved = -1;
      }
  }
} // namespace nlmech
