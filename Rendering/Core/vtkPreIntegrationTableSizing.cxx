// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkPreIntegrationTableSizing.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPreIntegrationTableRefiner.h"
#include "vtkPreIntegrationTableSizer.h"
#include "vtkSecondOrderPreIntegrationTable.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkPreIntegrationTableSizing);

//------------------------------------------------------------------------------
vtkPreIntegrationTableSizing::vtkPreIntegrationTableSizing()
  : Sizer(vtkPreIntegrationTableSizer::New())
  , Refiner(vtkPreIntegrationTableRefiner::New())
  , MeasuredSignature(vtkDoubleArray::New())
{
}

//------------------------------------------------------------------------------
vtkPreIntegrationTableSizing::~vtkPreIntegrationTableSizing()
{
  this->Refiner->Delete();
  this->Sizer->Delete();
  this->MeasuredSignature->Delete();
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::Reset()
{
  this->RangeKept = false;
  this->Key.clear();
  this->DataKey.clear();
  this->MeasuredSignature->Initialize();
  this->Interim = false;
  this->Request = 0;
  this->RequestTable = nullptr;
  this->Refiner->Cancel();
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::MarkMeasured(vtkSecondOrderPreIntegrationTable* table)
{
  const auto found = std::find(this->MeasuredTables.begin(), this->MeasuredTables.end(), table);
  const size_t index = static_cast<size_t>(found - this->MeasuredTables.begin());
  if (found == this->MeasuredTables.end())
  {
    this->MeasuredTables.push_back(table);
    this->MeasuredSizes.emplace_back();
  }
  this->MeasuredSizes[index] = { static_cast<double>(table->GetTableSize()),
    static_cast<double>(table->GetChordSize()),
    table->GetChordRange(),
    static_cast<double>(table->GetDeviationSize()),
    table->GetDeviationRange(),
    table->GetPrefilter() ? 1.0 : 0.0 };
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizing::Update(const std::vector<double>& key,
  const std::vector<double>& dataKey,
  vtkImageData* volume,
  vtkDataArray* scalars,
  vtkSecondOrderPreIntegrationTable* table,
  int order,
  double sampleDistance,
  int deviationLimit,
  bool buildEntries)
{
  if (!table)
  {
    return false;
  }
  const bool sameSettings = key == this->Key && !this->Key.empty();
  if (sameSettings && dataKey != this->DataKey && !this->Interim && this->ReuseForNewData &&
    this->MeasuredSignature->GetNumberOfTuples() > 0 && volume && scalars &&
    std::find(this->MeasuredTables.begin(), this->MeasuredTables.end(), table) !=
      this->MeasuredTables.end())
  {
    // New data alone (a time step): the measured sizes stay, with the scalar range they were
    // measured over (the same entries relative to the transfer function: a table chosen for
    // how its entries fall on a narrow feature keeps them so), while that range holds the new
    // values and their distribution and chords are close to those they were measured on.
    // Values beyond that range extend it by whole centre spacings (the entries stay where
    // they were), by at most a quarter of it.
    const double* range = table->GetScalarRange();
    const double* measured = this->MeasuredRange;
    const int n = this->MeasuredSize;
    const double spacing = n > 1 ? (measured[1] - measured[0]) / (n - 1) : 0.0;
    this->LastDistributionShift = VTK_DOUBLE_MAX;
    this->LastChordChange = VTK_DOUBLE_MAX;
    double below = 0.0, above = 0.0;
    if (spacing > 0.0)
    {
      below = std::max(0.0, std::ceil((measured[0] - range[0]) / spacing - 1e-9));
      above = std::max(0.0, std::ceil((range[1] - measured[1]) / spacing - 1e-9));
    }
    const double extended[2] = { measured[0] - below * spacing, measured[1] + above * spacing };
    if (spacing > 0.0 && below + above <= 0.25 * (n - 1))
    {
      vtkNew<vtkDoubleArray> signature;
      ComputeSignature(scalars, volume->GetDimensions(), extended, signature);
      this->LastDistributionShift = DistributionShift(this->MeasuredSignature, signature);
      this->LastChordChange = ChordChange(this->MeasuredSignature, signature);
    }
    if (this->LastDistributionShift <= this->MaximumDistributionShift &&
      this->LastChordChange <= this->MaximumChordChange)
    {
      this->KeptRange[0] = extended[0];
      this->KeptRange[1] = extended[1];
      this->KeptTableSize = n + static_cast<int>(below + above);
      this->RangeKept = true;
      table->SetScalarRange(this->KeptRange);
      table->SetTableSize(this->KeptTableSize);
      this->DataKey = dataKey;
      ++this->NumberOfKeptSizes;
      return true;
    }
  }
  if (sameSettings && dataKey == this->DataKey)
  {
    if (this->RangeKept)
    {
      // The caller sets the data's range at every frame: the kept one stands.
      table->SetScalarRange(this->KeptRange);
      table->SetTableSize(this->KeptTableSize);
    }
    if (!this->Interim)
    {
      return true;
    }
    const bool provisional = this->Refiner->IsProvisional(this->Request);
    if (this->Refiner->TakeResult(this->Request, table))
    {
      if (provisional)
      {
        // The last measured sizes, built for this change: drawn until the measurement ends.
        ++this->NumberOfProvisionalTables;
        return true;
      }
      this->FinishRefinement(table);
      return true;
    }
    if (this->Refiner->Failed(this->Request))
    {
      // The interim table stays: it is a table of the right transfer functions, only not
      // of measured sizes.
      vtkErrorMacro("The table sizes could not be measured in the background ("
        << this->Refiner->GetFailure(this->Request) << "); the interim table stays.");
      this->Interim = false;
    }
    return true;
  }

  this->Key = key;
  this->DataKey = dataKey;
  this->Interim = false;
  this->RangeKept = false;
  this->Request = 0;
  table->GetScalarRange(this->MeasuredRange);
  if (volume && scalars)
  {
    ComputeSignature(
      scalars, volume->GetDimensions(), this->MeasuredRange, this->MeasuredSignature);
  }
  if (!this->RefineInBackground)
  {
    this->Refiner->Cancel();
    if (!this->Sizer->Choose(volume, scalars, table, order, sampleDistance))
    {
      this->Key.clear();
      return false;
    }
    if (order == 2)
    {
      table->SetDeviationSize(std::min(table->GetDeviationSize(), std::max(deviationLimit, 1)));
    }
    this->MeasuredSize = table->GetTableSize();
    this->MarkMeasured(table);
    return true;
  }

  this->Refiner->GetSizerSettings()->CopySettings(this->Sizer);
  // Sizes measured before are built first, as a provisional table: a small edit most often
  // measures them again, and the measurement takes longer than their build. The table may
  // hold interim sizes (a drag): the request takes its last measured ones.
  const auto found = std::find(this->MeasuredTables.begin(), this->MeasuredTables.end(), table);
  const bool measured = found != this->MeasuredTables.end();
  if (measured && this->ProvisionalTables)
  {
    const std::vector<double>& last = this->MeasuredSizes[found - this->MeasuredTables.begin()];
    table->SetTableSize(static_cast<int>(last[0]));
    table->SetChordSize(static_cast<int>(last[1]));
    table->SetChordRange(last[2]);
    table->SetDeviationSize(static_cast<int>(last[3]));
    table->SetDeviationRange(last[4]);
    table->SetPrefilter(last[5] != 0.0);
  }
  // Those sizes are drawn at once when their rebuild for the change integrates no more entries
  // than an interim table, or is incremental and takes at most a fraction of a frame at the
  // table's last build rate (a narrow edit of the transfer functions, the table last built at
  // them): the frame then draws the provisional table itself.
  bool immediate = false;
  if (measured && this->ProvisionalTables && buildEntries)
  {
    const double rebuild = static_cast<double>(table->GetNumberOfEntriesToBuild());
    const double rate = table->GetLastBuildEntries() > 0
      ? table->GetLastBuildTime() / static_cast<double>(table->GetLastBuildEntries())
      : VTK_DOUBLE_MAX;
    const double budget = this->FrameTime > 0.0 ? this->ImmediateBuildFraction * this->FrameTime
                                                : this->ImmediateBuildTime;
    immediate = rebuild <= this->InterimEntries ||
      (rebuild < static_cast<double>(table->GetNumberOfEntries()) && rebuild * rate <= budget);
  }
  this->Request = this->Refiner->Request(volume,
    scalars,
    table,
    order,
    sampleDistance,
    deviationLimit,
    buildEntries,
    measured && this->ProvisionalTables && !immediate,
    immediate);
  if (this->Request <= 0)
  {
    this->Key.clear();
    return false;
  }
  this->RequestTable = table;
  this->Interim = true;
  if (immediate)
  {
    ++this->NumberOfProvisionalTables;
    return true;
  }
  ++this->NumberOfInterimTables;
  this->SetInterimSizes(table, order, deviationLimit);
  return true;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::SetInterimSizes(vtkSecondOrderPreIntegrationTable* table,
  int order,
  int deviationLimit)
{
  const bool measured =
    std::find(this->MeasuredTables.begin(), this->MeasuredTables.end(), table) !=
    this->MeasuredTables.end();
  int sizes[3];
  if (measured)
  {
    sizes[0] = table->GetTableSize();
    sizes[1] = table->GetChordSize();
    sizes[2] = order == 2 ? table->GetDeviationSize() : 1;
  }
  else
  {
    // Every chord and deviation the range allows: what any data produces at any step.
    const int n = order == 2 ? 65 : 129;
    sizes[0] = n;
    sizes[1] = n;
    sizes[2] = order == 2 ? n : 1;
    table->SetChordRange(0.0);
    table->SetDeviationRange(0.0);
  }
  sizes[2] = std::min(sizes[2], std::max(deviationLimit, 1));
  // Halve the axes (2^k + 1 entries stay so, odd chord and deviation axes stay odd) until
  // the table is within InterimEntries.
  auto entries = [&]() { return static_cast<double>(sizes[0]) * sizes[1] * sizes[2]; };
  while (entries() > this->InterimEntries && (sizes[0] > 3 || sizes[1] > 3 || sizes[2] > 3))
  {
    for (int& size : sizes)
    {
      if (size > 3)
      {
        size = (size - 1) / 2 + ((size - 1) / 2) % 2 + 1;
      }
    }
  }
  table->SetTableSize(std::max(sizes[0], 2));
  table->SetChordSize(sizes[1]);
  table->SetDeviationSize(sizes[2]);
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::ComputeSignature(vtkDataArray* scalars,
  const int dims[3],
  const double range[2],
  vtkDoubleArray* signature)
{
  constexpr int Bins = 64;
  signature->SetNumberOfComponents(1);
  signature->SetNumberOfTuples(3 + Bins);
  signature->FillValue(0.0);
  signature->SetValue(0, range[0]);
  signature->SetValue(1, range[1]);
  const double width = range[1] - range[0];
  if (!scalars || !(width > 0.0) || dims[0] < 1 || dims[1] < 1 || dims[2] < 1)
  {
    return;
  }
  // A regular subsample: every stride-th row and slice, every point along x (the chords need
  // neighbours), about a million points in all.
  const double points = static_cast<double>(dims[0]) * dims[1] * dims[2];
  const int stride = std::max(1, static_cast<int>(std::ceil(std::sqrt(points / 1048576.0))));
  auto binOf = [&](double value)
  { return std::min(std::max(static_cast<int>((value - range[0]) / width * Bins), 0), Bins - 1); };
  std::vector<double> histogram(Bins, 0.0);
  std::vector<double> differences;
  double counted = 0.0;
  for (int z = 0; z < dims[2]; z += stride)
  {
    for (int y = 0; y < dims[1]; y += stride)
    {
      const vtkIdType row =
        static_cast<vtkIdType>(dims[0]) * (y + static_cast<vtkIdType>(dims[1]) * z);
      double previous = std::nan("");
      for (int x = 0; x < dims[0]; ++x)
      {
        const double value = scalars->GetComponent(row + x, 0);
        if (std::isnan(value))
        {
          previous = value;
          continue;
        }
        histogram[binOf(value)] += 1.0;
        counted += 1.0;
        if (!std::isnan(previous))
        {
          differences.push_back(std::abs(value - previous));
        }
        previous = value;
      }
    }
  }
  for (int b = 0; b < Bins; ++b)
  {
    signature->SetValue(3 + b, counted > 0.0 ? histogram[b] / counted : 0.0);
  }
  if (!differences.empty())
  {
    const size_t at = std::min(
      differences.size() - 1, static_cast<size_t>(0.99 * static_cast<double>(differences.size())));
    std::nth_element(differences.begin(), differences.begin() + at, differences.end());
    signature->SetValue(2, differences[at] / width);
  }
}

//------------------------------------------------------------------------------
double vtkPreIntegrationTableSizing::DistributionShift(vtkDoubleArray* a, vtkDoubleArray* b)
{
  const vtkIdType n = a ? a->GetNumberOfTuples() : 0;
  if (!b || n < 4 || b->GetNumberOfTuples() != n)
  {
    return VTK_DOUBLE_MAX;
  }
  const int bins = static_cast<int>(n - 3);
  const double a0 = a->GetValue(0), aw = a->GetValue(1) - a->GetValue(0);
  const double b0 = b->GetValue(0), bw = b->GetValue(1) - b->GetValue(0);
  if (!(aw > 0.0) || !(bw > 0.0))
  {
    return VTK_DOUBLE_MAX;
  }
  // The cumulative distributions, linear within each bin, compared on a fine grid over both
  // ranges: the integral of |F_a - F_b| is the earth mover's distance.
  auto cdf = [bins](vtkDoubleArray* h, double low, double w, double s)
  {
    const double x = (s - low) / w * bins;
    if (x <= 0.0)
    {
      return 0.0;
    }
    double sum = 0.0;
    const int full = std::min(static_cast<int>(x), bins);
    for (int k = 0; k < full; ++k)
    {
      sum += h->GetValue(3 + k);
    }
    if (full < bins)
    {
      sum += (x - full) * h->GetValue(3 + full);
    }
    return sum;
  };
  const double low = std::min(a0, b0), high = std::max(a0 + aw, b0 + bw);
  constexpr int Steps = 1024;
  const double dx = (high - low) / Steps;
  double distance = 0.0;
  for (int k = 0; k < Steps; ++k)
  {
    const double s = low + (k + 0.5) * dx;
    distance += std::abs(cdf(a, a0, aw, s) - cdf(b, b0, bw, s)) * dx;
  }
  return distance / aw;
}

//------------------------------------------------------------------------------
double vtkPreIntegrationTableSizing::ChordChange(vtkDoubleArray* a, vtkDoubleArray* b)
{
  if (!a || !b || a->GetNumberOfTuples() < 3 || b->GetNumberOfTuples() < 3)
  {
    return VTK_DOUBLE_MAX;
  }
  // In data units: each chord is a fraction of its own range's width.
  const double ca = a->GetValue(2) * (a->GetValue(1) - a->GetValue(0));
  const double cb = b->GetValue(2) * (b->GetValue(1) - b->GetValue(0));
  if (!(ca > 0.0) || !(cb > 0.0))
  {
    return ca == cb ? 0.0 : VTK_DOUBLE_MAX;
  }
  return std::abs(std::log(cb / ca));
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::FinishRefinement(vtkSecondOrderPreIntegrationTable* table)
{
  this->Refiner->GetLastSizer(this->Sizer);
  this->Interim = false;
  this->MeasuredSize = table->GetTableSize();
  this->MarkMeasured(table);
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::FinishConfirmation()
{
  if (this->Interim && this->RequestTable && this->Refiner->IsConfirmation(this->Request) &&
    this->Refiner->TakeResult(this->Request, this->RequestTable))
  {
    this->FinishRefinement(this->RequestTable);
  }
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizing::IsRefining()
{
  this->FinishConfirmation();
  return this->Interim;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizing::IsRefinementReady()
{
  this->FinishConfirmation();
  return this->Interim &&
    (this->Refiner->IsReady(this->Request) || this->Refiner->Failed(this->Request));
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::WaitForRefinement()
{
  if (this->Interim)
  {
    this->Refiner->Wait();
  }
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "RefineInBackground: " << this->RefineInBackground << "\n";
  os << indent << "InterimEntries: " << this->InterimEntries << "\n";
  os << indent << "ImmediateBuildTime: " << this->ImmediateBuildTime << "\n";
  os << indent << "ImmediateBuildFraction: " << this->ImmediateBuildFraction << "\n";
  os << indent << "FrameTime: " << this->FrameTime << "\n";
  os << indent << "NumberOfInterimTables: " << this->NumberOfInterimTables << "\n";
  os << indent << "ProvisionalTables: " << this->ProvisionalTables << "\n";
  os << indent << "NumberOfProvisionalTables: " << this->NumberOfProvisionalTables << "\n";
  os << indent << "Interim: " << this->Interim << "\n";
}
