// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkPreIntegrationTableRefiner.h"

#include "vtkBackgroundWorker.h"
#include "vtkCallbackCommand.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPreIntegrationTableSizer.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>

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
  // A provisional table first, of the request's table's sizes, ranges and prefilter.
  bool Provisional = false;
  bool Drawn = false; // the caller draws the kept sizes: finding them again is a confirmation
  int KeptSizes[3] = { 2, 1, 1 };
  double KeptRanges[2] = { 0.0, 0.0 };
  bool KeptPrefilter = false;
  const std::atomic<bool>* Stopped = nullptr; // the worker's stop flag, while it runs
  vtkNew<vtkPreIntegrationTableSizer> Settings;
};
}

struct vtkPreIntegrationTableRefiner::vtkInternals
{
  vtkBackgroundWorker Worker;
  std::mutex Mutex; // guards what follows, up to the worker-thread state
  // The newest request's outcome: its number, its table (null when it failed).
  vtkIdType ResultId = 0;
  bool ResultFailed = false;
  vtkSmartPointer<vtkSecondOrderPreIntegrationTable> Result;
  // Whether Result is provisional, and whether the final result is the provisional table
  // already taken (nothing to give but the end of the request).
  bool ResultProvisional = false;
  bool ResultSame = false;
  Snapshot<vtkColorTransferFunction> Color;
  Snapshot<vtkPiecewiseFunction> Gray;
  Snapshot<vtkPiecewiseFunction> Opacity;
  // The table being built, so that a newer request can stop its build.
  vtkSecondOrderPreIntegrationTable* Building = nullptr;
  // The worker's error messages are kept, not printed from its thread: the last one of the
  // running job, and the one of the newest failed request.
  std::string JobError;
  std::string ResultError;
  // Statistics of the last completed request, copied out of the worker.
  vtkNew<vtkPreIntegrationTableSizer> Statistics;

  // Worker-thread state: the sizer (its rays, pieces and reference kept across requests) and
  // the table it measures with (its sampler kept while the transfer functions are, so that
  // the sizer keeps the reference).
  vtkNew<vtkPreIntegrationTableSizer> Sizer;
  vtkNew<vtkSecondOrderPreIntegrationTable> Measured;
  vtkNew<vtkCallbackCommand> ErrorCatcher;
  // Entries the next provisional table starts from, so that it integrates only those that read
  // what the change reached: the caller's, taken at a request while its table held the kept
  // sizes; else those of the provisional table of a request stopped by a newer one (its build
  // stopped part way, or done and perhaps taken), as in a drag, whose frames draw interim
  // tables. Guarded by Mutex.
  vtkSmartPointer<vtkSecondOrderPreIntegrationTable> Spare;

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

  // What a request runs in the worker: the sizes and the build, the result kept unless a newer
  // request stopped it.
  bool Run(const Job& job, const std::atomic<bool>& stop)
  {
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->JobError.clear();
    }
    bool stopped = false, same = false;
    vtkSmartPointer<vtkSecondOrderPreIntegrationTable> built = this->Work(job, stopped, same);
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->Building = nullptr;
    if (stopped || stop)
    {
      return false;
    }
    this->ResultId = job.Id;
    this->ResultFailed = !built;
    this->ResultError = built ? std::string() : this->JobError;
    if (same && this->Result && this->ResultProvisional)
    {
      this->ResultProvisional = false; // not taken yet: the provisional table is the result
    }
    else if (same)
    {
      this->ResultSame = true; // taken: the table has it already
    }
    else
    {
      this->Result = built;
      this->ResultProvisional = false;
    }
    if (built)
    {
      this->Statistics->CopyStatistics(this->Sizer);
    }
    return built != nullptr;
  }

  // Chooses the sizes and builds the table of a job; null on failure, or when stopped (then
  // `stopped` is set). With a provisional table given first, `same` tells that the sizes chosen
  // are its own (the table returned is then that table).
  vtkSmartPointer<vtkSecondOrderPreIntegrationTable> Work(const Job& job, bool& stopped, bool& same)
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
    this->Sizer->SetLowPriority(job.LowPriority);
    this->Sizer->CopySettings(job.Settings);
    vtkSmartPointer<vtkSecondOrderPreIntegrationTable> provisional;
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      provisional = job.Provisional && job.BuildEntries ? this->Spare : nullptr;
      this->Spare = nullptr;
    }
    // Stopped by a newer request: the provisional table's entries are kept for it, unless it
    // gave the caller's.
    auto keep = [&]()
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      if (stopped && !this->Spare)
      {
        this->Spare = provisional;
      }
    };
    if (job.Provisional && job.BuildEntries)
    {
      const double ranges[2] = { job.KeptRanges[0], job.KeptRanges[1] };
      if (!this->Build(job, job.KeptSizes, ranges, job.KeptPrefilter, stopped, provisional))
      {
        keep();
        return nullptr;
      }
      std::lock_guard<std::mutex> lock(this->Mutex);
      if (job.Stopped && *job.Stopped)
      {
        stopped = true;
        this->Spare = this->Spare ? this->Spare : provisional;
        return nullptr;
      }
      this->Building = nullptr;
      this->ResultId = job.Id;
      this->ResultFailed = false;
      this->Result = provisional;
      this->ResultProvisional = true;
    }
    if (!this->Sizer->Choose(job.Volume, job.Scalars, measured, job.Order, job.SampleDistance))
    {
      stopped = this->Sizer->GetAborted();
      keep();
      return nullptr;
    }
    const int sizes[3] = { measured->GetTableSize(),
      measured->GetChordSize(),
      std::min(measured->GetDeviationSize(), std::max(job.DeviationLimit, 1)) };
    const double ranges[2] = { measured->GetChordRange(), measured->GetDeviationRange() };
    if ((provisional || job.Drawn) && std::equal(sizes, sizes + 3, job.KeptSizes) &&
      ranges[0] == job.KeptRanges[0] && ranges[1] == job.KeptRanges[1] &&
      measured->GetPrefilter() == job.KeptPrefilter)
    {
      same = true;
      if (provisional)
      {
        return provisional;
      }
      return vtkSmartPointer<vtkSecondOrderPreIntegrationTable>(measured);
    }
    vtkSmartPointer<vtkSecondOrderPreIntegrationTable> table;
    return this->Build(job, sizes, ranges, measured->GetPrefilter(), stopped, table) ? table
                                                                                     : nullptr;
  }

  // Sets table (a new one when null, else one whose entries it starts from) to the job's table
  // at the given sizes, chord and deviation ranges and prefilter, and builds its entries on
  // the CPU when the job asks for them; false on failure or when stopped.
  bool Build(const Job& job,
    const int sizes[3],
    const double ranges[2],
    bool prefilter,
    bool& stopped,
    vtkSmartPointer<vtkSecondOrderPreIntegrationTable>& table)
  {
    vtkVolumeTransferFunctionSampler* sampler = this->Measured->GetSampler();
    if (!table)
    {
      table = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
      table->AddObserver(vtkCommand::ErrorEvent, this->ErrorCatcher);
    }
    vtkVolumeTransferFunctionSampler* own = table->GetSampler();
    own->SetFromSampler(sampler);
    table->SetScalarRange(job.Range[0], job.Range[1]);
    table->SetSegmentLength(job.SegmentLength);
    table->SetIterations(job.Iterations);
    table->SetPrefilter(prefilter);
    table->SetMoments(job.Moments);
    table->SetSlabMoments(job.SlabMoments);
    table->SetTableSize(sizes[0]);
    table->SetChordSize(sizes[1]);
    table->SetChordRange(ranges[0]);
    table->SetDeviationSize(sizes[2]);
    table->SetDeviationRange(ranges[1]);
    table->SetComputeEntries(job.BuildEntries);
    table->SetLowPriority(job.LowPriority);
    if (job.BuildEntries)
    {
      {
        std::lock_guard<std::mutex> lock(this->Mutex);
        if (job.Stopped && *job.Stopped)
        {
          stopped = true; // superseded while measuring
          return false;
        }
        this->Building = table;
      }
      if (!table->Update())
      {
        stopped = table->GetAbortBuild();
        return false;
      }
    }
    return true;
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
  // The worker stops and joins first (its member is destroyed last of the internals' users).
  this->Internals->Worker.Cancel();
  this->Internals->Worker.Wait();
  this->SizerSettings->Delete();
}

//------------------------------------------------------------------------------
vtkIdType vtkPreIntegrationTableRefiner::Request(vtkImageData* volume,
  vtkDataArray* scalars,
  vtkSecondOrderPreIntegrationTable* table,
  int order,
  double sampleDistance,
  int deviationLimit,
  bool buildEntries,
  bool provisional,
  bool drawn)
{
  if (!volume || !scalars || !table || (order != 1 && order != 2))
  {
    vtkErrorMacro("A refinement needs a volume, its scalars, a table and order 1 or 2.");
    return 0;
  }
  vtkInternals& I = *this->Internals;
  auto job = std::make_shared<Job>();
  vtkVolumeTransferFunctionSampler* sampler = table->GetSampler();
  job->Volume = volume;
  job->Scalars = scalars;
  {
    std::lock_guard<std::mutex> lock(I.Mutex);
    job->Color = I.Color.Of(sampler->GetColor());
    job->Gray = I.Gray.Of(sampler->GetGrayColor());
    job->Opacity = I.Opacity.Of(sampler->GetScalarOpacity());
    I.Result = nullptr;
    I.ResultId = 0;
    I.ResultProvisional = false;
    I.ResultSame = false;
  }
  job->Provisional = provisional && buildEntries && !drawn;
  job->Drawn = drawn;
  job->KeptSizes[0] = table->GetTableSize();
  job->KeptSizes[1] = table->GetChordSize();
  job->KeptSizes[2] = std::min(table->GetDeviationSize(), std::max(deviationLimit, 1));
  job->KeptRanges[0] = table->GetChordRange();
  job->KeptRanges[1] = table->GetDeviationRange();
  job->KeptPrefilter = table->GetPrefilter();
  if (job->Provisional)
  {
    // The caller draws other sizes until the result comes: its entries move to the worker.
    auto seed = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
    seed->AddObserver(vtkCommand::ErrorEvent, I.ErrorCatcher);
    if (seed->TakeEntries(table))
    {
      std::lock_guard<std::mutex> lock(I.Mutex);
      I.Spare = seed;
    }
  }
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

  const vtkIdType request = I.Worker.Submit(
    [&I, job](vtkIdType id, const std::atomic<bool>& stop)
    {
      job->Id = id;
      job->Stopped = &stop;
      I.Sizer->ClearAbort();
      if (stop)
      {
        I.Sizer->Abort(); // stopped before the abort was cleared
      }
      return I.Run(*job, stop);
    },
    [&I]()
    {
      // Stops the running job at its next check (the worker's lock is held).
      I.Sizer->Abort();
      std::lock_guard<std::mutex> lock(I.Mutex);
      if (I.Building)
      {
        I.Building->SetAbortBuild(true);
      }
    });
  if (request <= 0)
  {
    vtkErrorMacro("The refinement thread could not start.");
  }
  return request;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableRefiner::Cancel()
{
  vtkInternals& I = *this->Internals;
  I.Worker.Cancel();
  std::lock_guard<std::mutex> lock(I.Mutex);
  I.Spare = nullptr;
  I.Result = nullptr;
  I.ResultId = 0;
  I.ResultProvisional = false;
  I.ResultSame = false;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableRefiner::IsBusy()
{
  vtkInternals& I = *this->Internals;
  const vtkIdType newest = I.Worker.GetNumberOfJobs();
  const int state = I.Worker.GetState(newest);
  return state == vtkBackgroundWorker::WAITING || state == vtkBackgroundWorker::RUNNING;
}

//------------------------------------------------------------------------------
double vtkPreIntegrationTableRefiner::GetProgress()
{
  if (!this->IsBusy())
  {
    return 1.0;
  }
  vtkInternals& I = *this->Internals;
  std::lock_guard<std::mutex> lock(I.Mutex);
  return I.Building ? 0.9 : 0.9 * I.Sizer->GetProgress();
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableRefiner::IsReady(vtkIdType request)
{
  vtkInternals& I = *this->Internals;
  std::lock_guard<std::mutex> lock(I.Mutex);
  return request > 0 && I.ResultId == request && (I.Result || I.ResultSame);
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableRefiner::IsProvisional(vtkIdType request)
{
  vtkInternals& I = *this->Internals;
  std::lock_guard<std::mutex> lock(I.Mutex);
  return request > 0 && I.ResultId == request && I.Result && I.ResultProvisional;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableRefiner::IsConfirmation(vtkIdType request)
{
  vtkInternals& I = *this->Internals;
  std::lock_guard<std::mutex> lock(I.Mutex);
  return request > 0 && I.ResultId == request && I.ResultSame;
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
    if (!table || request <= 0 || I.ResultId != request || !(I.Result || I.ResultSame))
    {
      return false;
    }
    if (I.ResultSame)
    {
      I.ResultSame = false; // the provisional table, already given, is the measured one
      return true;
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
  this->Internals->Worker.Wait();
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableRefiner::SetPaused(bool paused)
{
  if (paused != this->Internals->Worker.GetPaused())
  {
    this->Internals->Worker.SetPaused(paused);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableRefiner::GetPaused()
{
  return this->Internals->Worker.GetPaused();
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
  return this->Internals->Worker.GetNumberOfJobs();
}

//------------------------------------------------------------------------------
vtkIdType vtkPreIntegrationTableRefiner::GetNumberOfCompleted()
{
  return this->Internals->Worker.GetNumberOfCompleted();
}

//------------------------------------------------------------------------------
vtkIdType vtkPreIntegrationTableRefiner::GetNumberOfStopped()
{
  return this->Internals->Worker.GetNumberOfStopped();
}

//------------------------------------------------------------------------------
double vtkPreIntegrationTableRefiner::GetLastRefinementTime()
{
  return this->Internals->Worker.GetLastJobTime();
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
