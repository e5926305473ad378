// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkPreIntegrationTable.h"

#include "vtkErrorForwarder.h"
#include "vtkFloatArray.h"
#include "vtkTimerLog.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <cmath>

//------------------------------------------------------------------------------
vtkPreIntegrationTable::vtkPreIntegrationTable()
  : Sampler(vtkVolumeTransferFunctionSampler::New())
  , Table(vtkFloatArray::New())
  , EmptyRuns(vtkFloatArray::New())
  , CoordinateTable(vtkFloatArray::New())
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
  this->CoordinateTable->Delete();
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
bool vtkPreIntegrationTable::Update()
{
  if (!(this->SegmentLength > 0.0) || !std::isfinite(this->SegmentLength))
  {
    vtkErrorMacro(
      "The segment length must be positive and finite, got " << this->SegmentLength << ".");
    return false;
  }
  if (!(this->ScalarRange[1] > this->ScalarRange[0]) || !std::isfinite(this->ScalarRange[0]) ||
    !std::isfinite(this->ScalarRange[1]))
  {
    vtkErrorMacro("The scalar range must be finite and non-empty, got ["
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
  vtkIdType entries = 1;
  for (int d = 0; d < this->GetNumberOfDimensions(); ++d)
  {
    entries *= this->TableSize;
  }
  const double start = vtkTimerLog::GetUniversalTime();
  this->Table->SetNumberOfTuples(this->ComputeEntries ? entries : 0);
  this->PlaceEntries();
  this->BuildTable();
  this->BuildEmptyRuns();
  this->LastBuildTime = vtkTimerLog::GetUniversalTime() - start;
  this->BuildCount++;
  this->BuildMTime = mtime;
  return true;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTable::BuildEmptyRuns()
{
  const int n = this->TableSize;
  this->EmptyRuns->SetNumberOfTuples(n - 1);
  int run = -1;
  bool inRun = false;
  for (int b = 0; b < n - 1; ++b)
  {
    // Exact: VTK's interpolation is monotone between nodes.
    const bool empty =
      this->Sampler->GetMaximumOpacity(this->EntryScalars[b], this->EntryScalars[b + 1]) <= 0.0;
    if (empty && !inRun)
    {
      ++run;
    }
    inRun = empty;
    this->EmptyRuns->SetValue(b, empty ? static_cast<float>(run) : -1.0f);
  }
}

//------------------------------------------------------------------------------
double vtkPreIntegrationTable::GetEntryScalar(int i) const
{
  return i >= 0 && i < static_cast<int>(this->EntryScalars.size()) ? this->EntryScalars[i]
                                                                   : this->ScalarRange[0];
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTable::PlaceEntries()
{
  const int n = this->TableSize;
  const double r0 = this->ScalarRange[0], r1 = this->ScalarRange[1];
  const int bins = CoordinateTexels - 1;
  const double binWidth = (r1 - r0) / bins;
  // Cumulative weight at the bin edges, normalised to [0, 1].
  std::vector<double> cumulative(bins + 1, 0.0);
  if (this->AdaptiveAxes)
  {
    const double feature = std::min(this->Sampler->GetSmallestOpacityFeature(), r1 - r0);
    const double margin = 2.0 * feature;
    std::vector<bool> active(bins);
    int count = 0;
    for (int k = 0; k < bins; ++k)
    {
      const double a = r0 + k * binWidth;
      active[k] = this->Sampler->GetMaximumOpacity(a - margin, a + binWidth + margin) > 0.0;
      count += active[k] ? 1 : 0;
    }
    // The inactive bins together weigh an eighth of the total (when there are both).
    const double idle = count > 0 && count < bins ? (count / 7.0) / (bins - count) : 1.0;
    for (int k = 0; k < bins; ++k)
    {
      cumulative[k + 1] = cumulative[k] + (active[k] ? 1.0 : idle);
    }
  }
  else
  {
    for (int k = 0; k < bins; ++k)
    {
      cumulative[k + 1] = k + 1.0;
    }
  }
  const double total = cumulative[bins];
  this->CoordinateTable->SetNumberOfTuples(bins + 1);
  for (int k = 0; k <= bins; ++k)
  {
    cumulative[k] /= total;
    this->CoordinateTable->SetValue(k, static_cast<float>((cumulative[k] * (n - 1) + 0.5) / n));
  }
  // Entry i where the cumulative weight reaches i / (n - 1); the ends exactly at the range.
  this->EntryScalars.resize(n);
  int k = 0;
  for (int i = 0; i < n; ++i)
  {
    const double target = static_cast<double>(i) / (n - 1);
    while (k < bins - 1 && cumulative[k + 1] < target)
    {
      ++k;
    }
    const double width = cumulative[k + 1] - cumulative[k];
    const double f = width > 0.0 ? (target - cumulative[k]) / width : 0.0;
    this->EntryScalars[i] = r0 + (k + std::min(std::max(f, 0.0), 1.0)) * binWidth;
  }
  this->EntryScalars[0] = r0;
  this->EntryScalars[n - 1] = r1;
  if (!this->AdaptiveAxes)
  {
    // Equispaced entries exactly as r0 + i (r1 - r0) / (n - 1), which the tables assume.
    for (int i = 1; i < n - 1; ++i)
    {
      this->EntryScalars[i] = r0 + i * (r1 - r0) / (n - 1);
    }
  }
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
  os << indent << "BuildCount: " << this->BuildCount << "\n";
  os << indent << "LastBuildTime: " << this->LastBuildTime << "\n";
}
