// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkBackgroundWorker
 * @brief   one worker thread for work that a renderer answers first and refines after, the
 *          newest request winning
 *
 * A renderer that draws a change at once with something cheap (interim table sizes, a full
 * sampling rate) submits the real work here: Submit() queues a job and stops the job that
 * runs (its Stop callback is called, and the stop flag the job reads is set), so that a drag
 * of edits works only on its last. The job runs in the worker's thread, which has low
 * priority (vtkLowPriorityThreads::LowerPriority); it returns true when it produced its
 * result, false when it failed. Its result is the submitter's business (the job writes it
 * where the submitter reads it after GetState() says DONE). Not wrapped.
 *
 * Thread safety: every method may be called from any thread; jobs run one at a time.
 */
#ifndef vtkBackgroundWorker_h
#define vtkBackgroundWorker_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkType.h"                 // For vtkIdType

#include <atomic>     // For the stop flag
#include <functional> // For the jobs
#include <memory>     // For std::unique_ptr

class HOVRRENDERINGCORE_EXPORT vtkBackgroundWorker
{
public:
  vtkBackgroundWorker();
  ~vtkBackgroundWorker();
  vtkBackgroundWorker(const vtkBackgroundWorker&) = delete;
  vtkBackgroundWorker& operator=(const vtkBackgroundWorker&) = delete;

  // A job: its work, given its number and the flag that says it is stopped (true when it
  // produced its result), and what stops it early when a newer job or Cancel() supersedes it
  // (called from the superseding thread; may be empty: the work then reads the flag).
  using Work = std::function<bool(vtkIdType job, const std::atomic<bool>& stop)>;
  using Stop = std::function<void()>;

  enum States
  {
    UNKNOWN = 0, ///< not a job of this worker, or superseded and forgotten
    WAITING,     ///< queued (or held by SetPaused)
    RUNNING,
    DONE,   ///< the newest job, finished with its result
    FAILED, ///< the newest job, finished without one
    STOPPED ///< superseded or cancelled before it finished
  };

  /**
   * Queue a job, replacing a queued one and stopping the running one. Returns its number
   * (positive), or 0 when the thread cannot start.
   */
  vtkIdType Submit(Work work, Stop stop = Stop());

  /**
   * Where job `job` stands. Only the newest job is remembered beyond its end.
   */
  int GetState(vtkIdType job);

  /**
   * Stop the running job and drop the queued one.
   */
  void Cancel();

  /**
   * Block until no job runs, and none is queued unless held by SetPaused.
   */
  void Wait();

  /**
   * Hold queued jobs without starting them (the running one goes on).
   */
  void SetPaused(bool paused);
  bool GetPaused();

  /**
   * Jobs submitted, finished with a result, and stopped (superseded or cancelled).
   */
  vtkIdType GetNumberOfJobs();
  vtkIdType GetNumberOfCompleted();
  vtkIdType GetNumberOfStopped();

  /**
   * Wall time in seconds of the last job that finished with its result.
   */
  double GetLastJobTime();

private:
  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
