// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkLowPriorityThreads.h"

#if defined(__linux__)
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <system_error>
#include <thread>
#include <vector>

namespace
{
// The nice value of a low-priority thread: about a tenth of a core beside threads of normal
// priority.
constexpr int LowNice = 10;
}

//------------------------------------------------------------------------------
void vtkLowPriorityThreads::LowerPriority()
{
#if defined(__linux__) && defined(SYS_gettid)
  // On Linux a nice value belongs to a thread, named by its thread id.
  const auto thread = static_cast<id_t>(syscall(SYS_gettid));
  errno = 0;
  const int current = getpriority(PRIO_PROCESS, thread);
  if (errno == 0 && current < LowNice)
  {
    setpriority(PRIO_PROCESS, thread, LowNice);
  }
#endif
}

//------------------------------------------------------------------------------
void vtkLowPriorityThreads::For(vtkIdType n,
  vtkIdType grain,
  const std::function<void(vtkIdType, vtkIdType)>& body)
{
  if (n <= 0)
  {
    return;
  }
  grain = std::max<vtkIdType>(grain, 1);
  std::atomic<vtkIdType> next{ 0 };
  auto work = [&]()
  {
    for (;;)
    {
      const vtkIdType begin = next.fetch_add(grain);
      if (begin >= n)
      {
        return;
      }
      body(begin, std::min(begin + grain, n));
    }
  };
  const vtkIdType chunks = (n + grain - 1) / grain;
  const int cores = static_cast<int>(std::max(std::thread::hardware_concurrency(), 1u));
  const int count = static_cast<int>(std::min<vtkIdType>(cores, chunks));
  std::vector<std::thread> threads;
  for (int t = 0; t < count; ++t)
  {
    try
    {
      threads.emplace_back(
        [&]()
        {
          LowerPriority();
          work();
        });
    }
    catch (const std::system_error&)
    {
      break;
    }
  }
  if (threads.empty())
  {
    work();
  }
  for (std::thread& thread : threads)
  {
    thread.join();
  }
}
