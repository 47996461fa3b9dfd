#include "plumage/common/cpu_time.h"

#include <sys/resource.h>

namespace plumage {

double process_cpu_seconds() {
  rusage ru{};
  if (getrusage(RUSAGE_SELF, &ru) != 0) return 0.0;
  const auto secs = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return secs(ru.ru_utime) + secs(ru.ru_stime);
}

}  // namespace plumage
