#pragma once
// Silences the process's standard error (file descriptor 2) while an instance lives: for libraries
// that print their own diagnostics on every expected failure (SUNDIALS KINSOL's error handler
// writes each failed solve to stderr, and deal.II 9.4's wrapper gives no access to it). Nested and
// concurrent instances share one redirection: the first silences, the last restores. Our own
// messages are printed after the scope ends, from what the library returned.

namespace nlmech
{
  class QuietStderr
  {
  public:
    QuietStderr();
    ~QuietStderr();
    QuietStderr(const QuietStderr &)            = delete;
    QuietStderr &operator=(const QuietStderr &) = delete;
  };
} // namespace nlmech
