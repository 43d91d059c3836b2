#pragma once
// A simulated full disk for the tests: a file-size limit (what `ulimit -f` sets) with
// SIGXFSZ ignored, so that writes past it fail with EFBIG instead of killing the test.

#include <csignal>
#include <sys/resource.h>

namespace plantnbv {
namespace test {

/// The limit holds for the scope (the whole process: use it in single-threaded code).
class FileSizeLimit {
public:
  explicit FileSizeLimit(rlim_t bytes)
  {
    ::getrlimit(RLIMIT_FSIZE, &saved_);
    previous_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit()
  {
    ::setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previous_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

private:
  rlimit saved_{};
  void (*previous_)(int) = nullptr;
};

} // namespace test
} // namespace plantnbv
