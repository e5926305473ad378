// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkPreIntegrationTableRefiner.h"

#include "vtkCallbackCommand.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkLowPriorityThreads.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPreIntegrationTableSizer.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkSmartPointer.h"
#include "vtkTimerLog.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <condition_variable>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>

vtkStandardNewMacro(vtkPreIntegrationTableRefiner);

namespace
{
// A transfer function as a request saw it: the caller's function, its modification time
// then, and the copy the worker reads.
template <class Function>
struct Snapshot
{
  Function* Source = nullptr;
  vtkMTimeType Time = 0;
  vtkSmartPointer<Function> Copy;

  // The copy of source, made anew only when source changed since the last one.
  Function* Of(Function* source)
  {
    if (!source)
    {
      this->Source = nullptr;
      this->Copy = nullptr;
      return nullptr;
    }
    if (source != this->Source || source->GetMTime() != this->Time || !this->Copy)
    {
      this->Copy = vtkSmartPointer<Function>::New();
      this->Copy->DeepCopy(source);
      this->Source = source;
      this->Time = source->GetMTime();
    }
    return this->Copy;
  }
};

// One request: all the worker reads.
struct Job
{
  vtkIdType Id = 0;
  vtkSmartPointer<vtkImageData> Volume;
  vtkSmartPointer<vtkDataArray> Scalars;
  vtkSmartPointer<vtkColorTransferFunction> Color;
  vtkSmartPointer<vtkPiecewiseFunction> Gray;
  vtkSmartPointer<vtkPiecewiseFunction> Opacity;
  double UnitDistance = 1.0;
  double MaximumOpacity = 1.0;
  double Range[2] = { 0.0, 1.0 };
  double SegmentLength = 1.0;
  int Iterations = 64;
  bool Prefilter = false;
  int Moments = 0;
  int SlabMoments = 0;
  int Order = 1;
  double SampleDistance = 1.0;
  int DeviationLimit = 1;
  bool BuildEntries = true;
  bool LowPriority = true;
  vtkNew<vtkPreIntegrationTableSizer> Settings;
};
}

struct vtkPreIntegrationTableRefiner::vtkInternals
{
  std::mutex Mutex;
  std::condition_variable Changed;
  std::thread Worker;
  bool Quit = false;
  bool Working = false;         // the worker holds a job
  bool Paused = false;          // requests wait without starting
  std::unique_ptr<Job> Pending; // the newest request, not yet started
  vtkIdType Newest = 0;         // the newest request's number
  vtkIdType Counter = 0;
  vtkIdType Completed = 0;
  vtkIdType Stopped = 0;
  // The newest request's outcome: its number, its table (null when it failed).
  vtkIdType ResultId = 0;
  bool ResultFailed = false;
  vtkSmartPointer<vtkSecondOrderPreIntegrationTable> Result;
  double LastTime = 0.0;
  Snapshot<vtkColorTransferFunction> Color;
  Snapshot<vtkPiecewiseFunction> Gray;
  Snapshot<vtkPiecewiseFunction> Opacity;

  // Worker-thread state: the sizer (its rays, pieces and reference kept across requests) and
  // the table it measures with (its sampler kept while the transfer functions are, so that
  // the sizer keeps the reference).
  vtkNew<vtkPreIntegrationTableSizer> Sizer;
  vtkNew<vtkSecondOrderPreIntegrationTable> Measured;
  // Statistics of the last completed request, copied out of the worker under the mutex.
  vtkNew<vtkPreIntegrationTableSizer> Statistics;
  // The table being built, so that a newer request can stop its build.
  vtkSecondOrderPreIntegrationTable* Building = nullptr;
  // The worker's error messages are kept, not printed from its thread: the last one of the
  // running job, and the one of the newest failed request.
  vtkNew<vtkCallbackCommand> ErrorCatcher;
  std::string JobError;
  std::string ResultError;

  static void CatchError(vtkObject*, unsigned long, void* clientData, void* callData)
  {
    auto* self = static_cast<vtkInternals*>(clientData);
    std::lock_guard<std::mutex> lock(self->Mutex);
    self->JobError = callData ? static_cast<const char*>(callData) : "unknown error";
  }

  vtkInternals()
  {
    this->ErrorCatcher->SetCallback(&vtkInternals::CatchError);
    this->ErrorCatcher->SetClientData(this);
    this->Sizer->AddObserver(vtkCommand::ErrorEvent, this->ErrorCatcher);
    this->Measured->AddObserver(vtkCommand::ErrorEvent, this->ErrorCatcher);
  }

  void Run()
  {
    for (;;)
    {
      std::unique_ptr<Job> job;
      {
        std::unique_lock<std::mutex> lock(this->Mutex);
        this->Changed.wait(lock, [this] { return this->Quit || (this->Pending && !this->Paused); });
        if (this->Quit)
        {
          return;
        }
        job = std::move(this->Pending);
        this->Working = true;
        this->JobError.clear();
        // Cleared under the lock: a request made after this point stops this job.
        this->Sizer->ClearAbort();
      }
      const double start = vtkTimerLog::GetUniversalTime();
      bool stopped = false;
      vtkSmartPointer<vtkSecondOrderPreIntegrationTable> built = this->Work(*job, stopped);
      const double elapsed = vtkTimerLog::GetUniversalTime() - start;
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->Working = false;
      this->Building = nullptr;
      if (job->Id == this->Newest && !stopped)
      {
        this->ResultId = job->Id;
        this->ResultFailed = !built;
        this->ResultError = built ? std::string() : this->JobError;
        this->Result = built;
        if (built)
        {
          ++this->Completed;
          this->LastTime = elapsed;
          this->Statistics->CopyStatistics(this->Sizer);
        }
      }
      else
      {
        ++this->Stopped;
      }
      this->Changed.notify_all();
    }
  }

  // Chooses the sizes and builds the table of a job; null on failure, or when stopped (then
  // `stopped` is set).
  vtkSmartPointer<vtkSecondOrderPreIntegrationTable> Work(const Job& job, bool& stopped)
  {
    vtkVolumeTransferFunctionSampler* sampler = this->Measured->GetSampler();
    sampler->SetColor(job.Color);
    sampler->SetGrayColor(job.Gray);
    sampler->SetScalarOpacity(job.Opacity);
    sampler->SetScalarOpacityUnitDistance(job.UnitDistance);
    sampler->SetMaximumOpacity(job.MaximumOpacity);
    vtkSecondOrderPreIntegrationTable* measured = this->Measured;
    measured->SetScalarRange(job.Range[0], job.Range[1]);
    measured->SetSegmentLength(job.SegmentLength);
    measured->SetIterations(job.Iterations);
    measured->SetPrefilter(job.Prefilter);
    measured->SetMoments(job.Moments);
    measured->SetSlabMoments(job.SlabMoments);
    if (job.LowPriority)
    {
      vtkLowPriorityThreads::LowerPriority();
    }
    this->Sizer->SetLowPriority(job.LowPriority);
    this->Sizer->CopySettings(job.Settings);
    if (!this->Sizer->Choose(job.Volume, job.Scalars, measured, job.Order, job.SampleDistance))
    {
      stopped = this->Sizer->GetAborted();
      return nullptr;
    }
    auto table = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
    table->AddObserver(vtkCommand::ErrorEvent, this->ErrorCatcher);
    vtkVolumeTransferFunctionSampler* own = table->GetSampler();
    own->SetFromSampler(sampler);
    table->SetScalarRange(job.Range[0], job.Range[1]);
    table->SetSegmentLength(job.SegmentLength);
    table->SetIterations(job.Iterations);
    table->SetPrefilter(measured->GetPrefilter());
    table->SetMoments(job.Moments);
    table->SetSlabMoments(job.SlabMoments);
    table->SetTableSize(measured->GetTableSize());
    table->SetChordSize(measured->GetChordSize());
    table->SetChordRange(measured->GetChordRange());
    table->SetDeviationSize(
      std::min(measured->GetDeviationSize(), std::max(job.DeviationLimit, 1)));
    table->SetDeviationRange(measured->GetDeviationRange());
    table->SetComputeEntries(job.BuildEntries);
    table->SetLowPriority(job.LowPriority);
    if (job.BuildEntries)
    {
      {
        std::lock_guard<std::mutex> lock(this->Mutex);
        if (job.Id != this->Newest)
        {
          stopped = true; // superseded while measuring
          return nullptr;
        }
        this->Building = table;
      }
      if (!table->Update())
      {
        stopped = table->GetAbortBuild();
        return nullptr;
      }
    }
    return table;
  }
};

//------------------------------------------------------------------------------
vtkPreIntegrationTableRefiner::vtkPreIntegrationTableRefiner()
  : SizerSettings(vtkPreIntegrationTableSizer::New())
  , Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkPreIntegrationTableRefiner::~vtkPreIntegrationTableRefiner()
{
  vtkInternals& I = *this->Internals;
  {
    std::lock_guard<std::mutex> lock(I.Mutex);
    I.Quit = true;
    I.Pending.reset();
    I.Sizer->Abort();
    if (I.Building)
    {
      I.Building->SetAbortBuild(true);
    }
  }
  I.Changed.notify_all();
  if (I.Worker.joinable())
  {
    I.Worker.join();
  }
  this->SizerSettings->Delete();
}

//------------------------------------------------------------------------------
vtkIdType vtkPreIntegrationTableRefiner::Request(vtkImageData* volume,
  vtkDataArray* scalars,
  vtkSecondOrderPreIntegrationTable* table,
  int order,
  double sampleDistance,
  int deviationLimit,
  bool buildEntries)
{
  if (!volume || !scalars || !table || (order != 1 && order != 2))
  {
    vtkErrorMacro("A refinement needs a volume, its scalars, a table and order 1 or 2.");
    return 0;
  }
  vtkInternals& I = *this->Internals;
  auto job = std::make_unique<Job>();
  vtkVolumeTransferFunctionSampler* sampler = table->GetSampler();
  job->Volume = volume;
  job->Scalars = scalars;
  job->Color = I.Color.Of(sampler->GetColor());
  job->Gray = I.Gray.Of(sampler->GetGrayColor());
  job->Opacity = I.Opacity.Of(sampler->GetScalarOpacity());
  job->UnitDistance = sampler->GetScalarOpacityUnitDistance();
  job->MaximumOpacity = sampler->GetMaximumOpacity();
  table->GetScalarRange(job->Range);
  job->SegmentLength = table->GetSegmentLength();
  job->Iterations = table->GetIterations();
  job->Prefilter = table->GetPrefilter();
  job->Moments = table->GetMoments();
  job->SlabMoments = table->GetSlabMoments();
  job->Order = order;
  job->SampleDistance = sampleDistance;
  job->DeviationLimit = deviationLimit;
  job->BuildEntries = buildEntries;
  job->LowPriority = this->LowPriority;
  job->Settings->CopySettings(this->SizerSettings);

  std::lock_guard<std::mutex> lock(I.Mutex);
  if (!I.Worker.joinable())
  {
    try
    {
      I.Worker = std::thread([&I] { I.Run(); });
    }
    catch (const std::system_error& e)
    {
      vtkErrorMacro("The refinement thread could not start: " << e.what());
      return 0;
    }
  }
  job->Id = ++I.Counter;
  I.Newest = job->Id;
  if (I.Pending)
  {
    ++I.Stopped; // replaced before it started
  }
  I.Pending = std::move(job);
  I.Result = nullptr;
  I.ResultId = 0;
  // The running job, if any, stops at its next check.
  I.Sizer->Abort();
  if (I.Building)
  {
    I.Building->SetAbortBuild(true);
  }
  I.Changed.notify_all();
  return I.Newest;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableRefiner::Cancel()
{
  vtkInternals& I = *this->Internals;
  std::lock_guard<std::mutex> lock(I.Mutex);
  if (I.Pending)
  {
    ++I.Stopped;
    I.Pending.reset();
  }
  I.Newest = 0;
  I.Result = nullptr;
  I.ResultId = 0;
  I.Sizer->Abort();
  if (I.Building)
  {
    I.Building->SetAbortBuild(true);
  }
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableRefiner::IsBusy()
{
  vtkInternals& I = *this->Internals;
  std::lock_guard<std::mutex> lock(I.Mutex);
  return I.Working || I.Pending;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableRefiner::IsReady(vtkIdType request)
{
  vtkInternals& I = *this->Internals;
  std::lock_guard<std::mutex> lock(I.Mutex);
  return request > 0 && I.ResultId == request && I.Result;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableRefiner::Failed(vtkIdType request)
{
  vtkInternals& I = *this->Internals;
  std::lock_guard<std::mutex> lock(I.Mutex);
  return request > 0 && I.ResultId == request && I.ResultFailed;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableRefiner::TakeResult(vtkIdType request,
  vtkSecondOrderPreIntegrationTable* table)
{
  vtkInternals& I = *this->Internals;
  vtkSmartPointer<vtkSecondOrderPreIntegrationTable> result;
  {
    std::lock_guard<std::mutex> lock(I.Mutex);
    if (!table || request <= 0 || I.ResultId != request || !I.Result)
    {
      return false;
    }
    result = I.Result;
    I.Result = nullptr;
  }
  table->SetPrefilter(result->GetPrefilter());
  table->SetTableSize(result->GetTableSize());
  table->SetChordSize(result->GetChordSize());
  table->SetChordRange(result->GetChordRange());
  table->SetDeviationSize(result->GetDeviationSize());
  table->SetDeviationRange(result->GetDeviationRange());
  if (result->GetComputeEntries() && table->GetComputeEntries())
  {
    // When the settings differ after all, table's next Update() builds the entries itself.
    table->AdoptBuild(result);
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableRefiner::Wait()
{
  vtkInternals& I = *this->Internals;
  std::unique_lock<std::mutex> lock(I.Mutex);
  I.Changed.wait(lock, [&I] { return !I.Working && (!I.Pending || I.Paused); });
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableRefiner::SetPaused(bool paused)
{
  vtkInternals& I = *this->Internals;
  {
    std::lock_guard<std::mutex> lock(I.Mutex);
    if (I.Paused == paused)
    {
      return;
    }
    I.Paused = paused;
  }
  I.Changed.notify_all();
  this->Modified();
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableRefiner::GetPaused()
{
  std::lock_guard<std::mutex> lock(this->Internals->Mutex);
  return this->Internals->Paused;
}

//------------------------------------------------------------------------------
std::string vtkPreIntegrationTableRefiner::GetFailure(vtkIdType request)
{
  vtkInternals& I = *this->Internals;
  std::lock_guard<std::mutex> lock(I.Mutex);
  return request > 0 && I.ResultId == request && I.ResultFailed ? I.ResultError : std::string();
}

//------------------------------------------------------------------------------
vtkIdType vtkPreIntegrationTableRefiner::GetNumberOfRequests()
{
  std::lock_guard<std::mutex> lock(this->Internals->Mutex);
  return this->Internals->Counter;
}

//------------------------------------------------------------------------------
vtkIdType vtkPreIntegrationTableRefiner::GetNumberOfCompleted()
{
  std::lock_guard<std::mutex> lock(this->Internals->Mutex);
  return this->Internals->Completed;
}

//------------------------------------------------------------------------------
vtkIdType vtkPreIntegrationTableRefiner::GetNumberOfStopped()
{
  std::lock_guard<std::mutex> lock(this->Internals->Mutex);
  return this->Internals->Stopped;
}

//------------------------------------------------------------------------------
double vtkPreIntegrationTableRefiner::GetLastRefinementTime()
{
  std::lock_guard<std::mutex> lock(this->Internals->Mutex);
  return this->Internals->LastTime;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableRefiner::GetLastSizer(vtkPreIntegrationTableSizer* into)
{
  std::lock_guard<std::mutex> lock(this->Internals->Mutex);
  if (into)
  {
    into->CopyStatistics(this->Internals->Statistics);
  }
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableRefiner::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LowPriority: " << this->LowPriority << "\n";
  os << indent << "NumberOfRequests: " << this->GetNumberOfRequests() << "\n";
  os << indent << "NumberOfCompleted: " << this->GetNumberOfCompleted() << "\n";
  os << indent << "NumberOfStopped: " << this->GetNumberOfStopped() << "\n";
}
