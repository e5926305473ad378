// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkPreIntegrationTable.h"

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkErrorForwarder.h"
#include "vtkFloatArray.h"
#include "vtkLowPriorityThreads.h"
#include "vtkSMPTools.h"
#include "vtkTimerLog.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <vtksys/SystemInformation.hxx>

#include <algorithm>
#include <cmath>
#include <new>
#include <vector>

//------------------------------------------------------------------------------
vtkPreIntegrationTable::vtkPreIntegrationTable()
  : Sampler(vtkVolumeTransferFunctionSampler::New())
  , Table(vtkFloatArray::New())
  , EmptyRuns(vtkFloatArray::New())
{
  this->Table->SetNumberOfComponents(4);
  this->Table->SetName("PreIntegrationTable");
  vtkErrorForwarder::Forward(this->Sampler, this);
}

//------------------------------------------------------------------------------
vtkPreIntegrationTable::~vtkPreIntegrationTable()
{
  this->Sampler->Delete();
  this->Table->Delete();
  this->EmptyRuns->Delete();
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTable::SetVolumeProperty(vtkVolumeProperty* property)
{
  this->Sampler->SetFromVolumeProperty(property);
}

//------------------------------------------------------------------------------
vtkIdType vtkPreIntegrationTable::GetMemorySize() const
{
  return this->Table->GetNumberOfValues() * static_cast<vtkIdType>(sizeof(float));
}

//------------------------------------------------------------------------------
vtkIdType vtkPreIntegrationTable::GetNumberOfEntries() const
{
  vtkIdType entries = 1;
  for (int d = 0; d < this->GetNumberOfDimensions(); ++d)
  {
    entries *= this->TableSize;
  }
  return entries;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTable::Update()
{
  // Tables are integrated in float.
  if (!(this->SegmentLength > 0.0) || !(this->SegmentLength <= 1e30))
  {
    vtkErrorMacro(
      "The segment length must be positive and at most 1e30, got " << this->SegmentLength << ".");
    return false;
  }
  if (!(this->ScalarRange[1] > this->ScalarRange[0]) ||
    !std::isfinite(this->ScalarRange[1] - this->ScalarRange[0]))
  {
    vtkErrorMacro("The scalar range must be finite, non-empty and narrower than the largest "
                  "double, got ["
      << this->ScalarRange[0] << ", " << this->ScalarRange[1] << "].");
    return false;
  }
  if (!this->Sampler->Prepare())
  {
    return false;
  }
  const vtkMTimeType mtime = std::max(this->GetMTime(), this->Sampler->GetMTime());
  if (mtime <= this->BuildMTime && this->BuildCount > 0)
  {
    return true;
  }
  // Settings changed and changed back (a range set by one caller and restored by another, a
  // transfer function rebuilt with the same nodes): the table is what it was.
  std::vector<double> key;
  this->AppendBuildKey(key);
  if (this->BuildCount > 0 &&
    this->Table->GetNumberOfTuples() == (this->ComputeEntries ? this->GetNumberOfEntries() : 0) &&
    key == this->BuildKey)
  {
    this->BuildMTime = mtime;
    return true;
  }
  this->BuildKey.clear();
  const vtkIdType entries = this->GetNumberOfEntries();
  const double start = vtkTimerLog::GetUniversalTime();
  // The table (16 bytes per entry) and the build's scratch are the only large allocations:
  // when memory runs out, an error rather than an exception through the caller.
  const vtkIdType wanted = this->ComputeEntries ? entries : 0;
  // Beyond physical memory the allocation may succeed by overcommit and the build be killed.
  vtksys::SystemInformation system;
  system.RunMemoryCheck();
  const double memory = 1048576.0 * static_cast<double>(system.GetTotalPhysicalMemory()); // MiB
  try
  {
    if (memory > 0.0 && static_cast<double>(wanted) * 4 * sizeof(float) > memory)
    {
      throw std::bad_alloc();
    }
    this->Table->SetNumberOfTuples(wanted);
    if (this->Table->GetNumberOfTuples() != wanted)
    {
      throw std::bad_alloc(); // vtkFloatArray reports the failure and keeps its old size
    }
    this->AbortBuild = this->BuildAborted = false;
    this->EntriesUnchanged = false;
    this->BuildTable();
    if (this->BuildAborted)
    {
      this->BuildKey.clear();
      if (!this->KeepsAbortedBuild())
      {
        this->Table->Initialize();
        this->TableReleased();
      }
      vtkErrorMacro("The build of the pre-integration table was aborted (AbortBuild).");
      return false;
    }
    this->BuildEmptyRuns();
  }
  catch (const std::bad_alloc&)
  {
    this->Table->Initialize();
    this->BuildKey.clear();
    this->TableReleased();
    vtkErrorMacro("Not enough memory for the pre-integration table of "
      << entries << " entries ("
      << static_cast<vtkIdType>(
           std::ceil(static_cast<double>(entries) * 4 * sizeof(float) / (1 << 20)))
      << " MiB); a smaller TableSize needs less.");
    return false;
  }
  this->LastBuildTime = vtkTimerLog::GetUniversalTime() - start;
  // A build that left every entry as it was (settings set back and forth) is no new table:
  // what was uploaded stands.
  if (!this->EntriesUnchanged)
  {
    this->BuildCount++;
  }
  this->BuildMTime = mtime;
  this->BuildKey = key;
  return true;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTable::AdoptBuild(vtkPreIntegrationTable* built)
{
  if (!built || built == this || built->BuildCount < 1 || !built->IsA(this->GetClassName()) ||
    built->TableSize != this->TableSize || built->SegmentLength != this->SegmentLength ||
    built->ScalarRange[0] != this->ScalarRange[0] ||
    built->ScalarRange[1] != this->ScalarRange[1] ||
    built->ComputeEntries != this->ComputeEntries ||
    built->GetNumberOfEntries() != this->GetNumberOfEntries() ||
    built->Table->GetNumberOfTuples() != (this->ComputeEntries ? this->GetNumberOfEntries() : 0))
  {
    return false;
  }
  // The sampler must be prepared as Update() prepares it: its nodes are what the table is
  // built for from now on.
  if (!this->Sampler->Prepare())
  {
    return false;
  }
  std::swap(this->Table, built->Table);
  std::swap(this->EmptyRuns, built->EmptyRuns);
  built->Table->Initialize();
  built->Table->SetNumberOfComponents(4);
  built->EmptyRuns->Initialize();
  built->BuildCount = 0;
  this->LastBuildTime = built->LastBuildTime;
  this->BuildCount++;
  this->BuildMTime = std::max(this->GetMTime(), this->Sampler->GetMTime());
  return true;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTable::AppendBuildKey(std::vector<double>& key) const
{
  key.insert(key.end(),
    { this->Sampler->GetContentHash(),
      this->ScalarRange[0],
      this->ScalarRange[1],
      static_cast<double>(this->TableSize),
      this->SegmentLength,
      this->ComputeEntries ? 1.0 : 0.0 });
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTable::BuildEmptyRuns()
{
  const int n = this->TableSize;
  const double spacing = (this->ScalarRange[1] - this->ScalarRange[0]) / (n - 1);
  this->EmptyRuns->SetNumberOfTuples(n - 1);
  int run = -1;
  bool inRun = false;
  for (int b = 0; b < n - 1; ++b)
  {
    const double s0 = this->ScalarRange[0] + b * spacing;
    // Exact: VTK's interpolation is monotone between nodes.
    const double margin = this->GetEmptyRunMargin();
    const bool empty = this->Sampler->GetMaximumOpacity(s0 - margin, s0 + spacing + margin) <= 0.0;
    if (empty && !inRun)
    {
      ++run;
    }
    inRun = empty;
    this->EmptyRuns->SetValue(b, empty ? static_cast<float>(run) : -1.0f);
  }
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTable::ComputeScalarRange(vtkDataArray* scalars,
  double dataRange[2],
  double tableRange[2],
  const double* cover)
{
  double range[2] = { 1.0, 0.0 };
  if (scalars && scalars->GetNumberOfTuples() > 0)
  {
    scalars->GetFiniteRange(range, 0);
  }
  if (!(range[0] <= range[1]))
  {
    return false;
  }
  if (cover && cover[0] <= cover[1] && std::isfinite(cover[0]) && std::isfinite(cover[1]))
  {
    range[0] = std::min(range[0], cover[0]);
    range[1] = std::max(range[1], cover[1]);
  }
  dataRange[0] = tableRange[0] = range[0];
  dataRange[1] = tableRange[1] = range[1];
  if (!(range[1] > range[0]))
  {
    tableRange[1] = range[0] + std::max(1.0, std::abs(range[0]) * 1e-6);
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkPreIntegrationTable::SuggestTableSize(int scalarType,
  const double range[2],
  vtkVolumeTransferFunctionSampler* sampler,
  int minimumSize,
  int maximumSize,
  double entriesPerFeature,
  bool opacityFeatures)
{
  const double width = range[1] - range[0];
  if (!(width > 0.0) || !std::isfinite(width))
  {
    return std::max(2, minimumSize);
  }
  const double feature = std::min(
    opacityFeatures ? sampler->GetSmallestOpacityFeature() : sampler->GetSmallestFeature(), width);
  const bool integer = !opacityFeatures && scalarType != VTK_FLOAT && scalarType != VTK_DOUBLE;
  if (integer)
  {
    // Put entries on every integer value (lookups at voxel values are exact), subdivided
    // when a feature is narrower than one unit or the table would be below the minimum size.
    double m = std::max(1.0, std::ceil(1.0 / feature));
    while (width * m + 1.0 < minimumSize)
    {
      m += 1.0;
    }
    if (width * m + 1.0 <= maximumSize)
    {
      return static_cast<int>(width * m + 1.0);
    }
  }
  const double wanted = std::ceil(entriesPerFeature * width / feature) + 1.0;
  return static_cast<int>(
    std::min(std::max(wanted, static_cast<double>(minimumSize)), static_cast<double>(maximumSize)));
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTable::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SegmentLength: " << this->SegmentLength << "\n";
  os << indent << "ScalarRange: " << this->ScalarRange[0] << " " << this->ScalarRange[1] << "\n";
  os << indent << "TableSize: " << this->TableSize << "\n";
  os << indent << "ComputeEntries: " << this->ComputeEntries << "\n";
  os << indent << "AbortBuild: " << this->AbortBuild << "\n";
  os << indent << "BuildCount: " << this->BuildCount << "\n";
  os << indent << "LastBuildTime: " << this->LastBuildTime << "\n";
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTable::ForInParts(vtkIdType n,
  const std::function<void(vtkIdType, vtkIdType)>& body)
{
  const int parts = static_cast<int>(std::min<vtkIdType>(n, 16));
  for (int part = 0; part < parts; ++part)
  {
    if (this->AbortBuild)
    {
      this->BuildAborted = true;
      return false;
    }
    if (this->LowPriority)
    {
      const vtkIdType begin = n * part / parts, end = n * (part + 1) / parts;
      vtkLowPriorityThreads::For(end - begin,
        std::max<vtkIdType>((end - begin) / 64, 1),
        [&](vtkIdType b, vtkIdType e) { body(begin + b, begin + e); });
    }
    else
    {
      vtkSMPTools::For(n * part / parts, n * (part + 1) / parts, body);
    }
    double progress = static_cast<double>(part + 1) / parts;
    this->InvokeEvent(vtkCommand::ProgressEvent, &progress);
  }
  return true;
}
