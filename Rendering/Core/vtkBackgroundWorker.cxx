// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkBackgroundWorker.h"

#include "vtkLowPriorityThreads.h"
#include "vtkTimerLog.h"

#include <condition_variable>
#include <mutex>
#include <system_error>
#include <thread>

struct vtkBackgroundWorker::vtkInternals
{
  struct Job
  {
    vtkIdType Id = 0;
    Work Run;
    Stop Halt;
  };

  std::mutex Mutex;
  std::condition_variable Changed;
  std::thread Thread;
  bool Quit = false;
  bool Paused = false;
  std::unique_ptr<Job> Pending;
  Job Running; // Id 0: none
  std::atomic<bool> StopFlag{ false };
  vtkIdType Counter = 0;
  vtkIdType Newest = 0;   // the newest job's number (0 after Cancel)
  vtkIdType Finished = 0; // the newest job, once it ended
  bool FinishedOk = false;
  vtkIdType Completed = 0;
  vtkIdType Stopped = 0;
  double LastTime = 0.0;

  // Under the lock: stop the running job.
  void StopRunning()
  {
    if (this->Running.Id != 0)
    {
      this->StopFlag = true;
      if (this->Running.Halt)
      {
        this->Running.Halt();
      }
    }
  }

  void Loop()
  {
    vtkLowPriorityThreads::LowerPriority();
    for (;;)
    {
      {
        std::unique_lock<std::mutex> lock(this->Mutex);
        this->Changed.wait(lock, [this] { return this->Quit || (this->Pending && !this->Paused); });
        if (this->Quit)
        {
          return;
        }
        this->Running = std::move(*this->Pending);
        this->Pending.reset();
        this->StopFlag = false;
      }
      const double start = vtkTimerLog::GetUniversalTime();
      const bool ok = this->Running.Run(this->Running.Id, this->StopFlag);
      const double elapsed = vtkTimerLog::GetUniversalTime() - start;
      std::lock_guard<std::mutex> lock(this->Mutex);
      const vtkIdType id = this->Running.Id;
      const bool stopped = this->StopFlag || id != this->Newest;
      this->Running = Job();
      if (stopped)
      {
        ++this->Stopped;
      }
      else
      {
        this->Finished = id;
        this->FinishedOk = ok;
        if (ok)
        {
          ++this->Completed;
          this->LastTime = elapsed;
        }
      }
      this->Changed.notify_all();
    }
  }
};

//------------------------------------------------------------------------------
vtkBackgroundWorker::vtkBackgroundWorker()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkBackgroundWorker::~vtkBackgroundWorker()
{
  vtkInternals& I = *this->Internals;
  {
    std::lock_guard<std::mutex> lock(I.Mutex);
    I.Quit = true;
    I.Pending.reset();
    I.StopRunning();
  }
  I.Changed.notify_all();
  if (I.Thread.joinable())
  {
    I.Thread.join();
  }
}

//------------------------------------------------------------------------------
vtkIdType vtkBackgroundWorker::Submit(Work work, Stop stop)
{
  vtkInternals& I = *this->Internals;
  std::lock_guard<std::mutex> lock(I.Mutex);
  if (!I.Thread.joinable())
  {
    try
    {
      I.Thread = std::thread([&I] { I.Loop(); });
    }
    catch (const std::system_error&)
    {
      return 0;
    }
  }
  if (I.Pending)
  {
    ++I.Stopped; // replaced before it started
  }
  I.Pending.reset(new vtkInternals::Job{ ++I.Counter, std::move(work), std::move(stop) });
  I.Newest = I.Counter;
  I.Finished = 0;
  I.StopRunning();
  I.Changed.notify_all();
  return I.Newest;
}

//------------------------------------------------------------------------------
int vtkBackgroundWorker::GetState(vtkIdType job)
{
  vtkInternals& I = *this->Internals;
  std::lock_guard<std::mutex> lock(I.Mutex);
  if (job <= 0)
  {
    return UNKNOWN;
  }
  if (I.Pending && I.Pending->Id == job)
  {
    return WAITING;
  }
  if (I.Running.Id == job)
  {
    return job == I.Newest && !I.StopFlag ? RUNNING : STOPPED;
  }
  if (I.Finished == job)
  {
    return I.FinishedOk ? DONE : FAILED;
  }
  return job > I.Counter ? UNKNOWN : STOPPED;
}

//------------------------------------------------------------------------------
void vtkBackgroundWorker::Cancel()
{
  vtkInternals& I = *this->Internals;
  std::lock_guard<std::mutex> lock(I.Mutex);
  if (I.Pending)
  {
    ++I.Stopped;
    I.Pending.reset();
  }
  I.Newest = 0;
  I.Finished = 0;
  I.StopRunning();
}

//------------------------------------------------------------------------------
void vtkBackgroundWorker::Wait()
{
  vtkInternals& I = *this->Internals;
  std::unique_lock<std::mutex> lock(I.Mutex);
  I.Changed.wait(lock, [&I] { return I.Running.Id == 0 && (!I.Pending || I.Paused); });
}

//------------------------------------------------------------------------------
void vtkBackgroundWorker::SetPaused(bool paused)
{
  vtkInternals& I = *this->Internals;
  {
    std::lock_guard<std::mutex> lock(I.Mutex);
    I.Paused = paused;
  }
  I.Changed.notify_all();
}

//------------------------------------------------------------------------------
bool vtkBackgroundWorker::GetPaused()
{
  std::lock_guard<std::mutex> lock(this->Internals->Mutex);
  return this->Internals->Paused;
}

//------------------------------------------------------------------------------
vtkIdType vtkBackgroundWorker::GetNumberOfJobs()
{
  std::lock_guard<std::mutex> lock(this->Internals->Mutex);
  return this->Internals->Counter;
}

//------------------------------------------------------------------------------
vtkIdType vtkBackgroundWorker::GetNumberOfCompleted()
{
  std::lock_guard<std::mutex> lock(this->Internals->Mutex);
  return this->Internals->Completed;
}

//------------------------------------------------------------------------------
vtkIdType vtkBackgroundWorker::GetNumberOfStopped()
{
  std::lock_guard<std::mutex> lock(this->Internals->Mutex);
  return this->Internals->Stopped;
}

//------------------------------------------------------------------------------
double vtkBackgroundWorker::GetLastJobTime()
{
  std::lock_guard<std::mutex> lock(this->Internals->Mutex);
  return this->Internals->LastTime;
}
