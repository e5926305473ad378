// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkSecondOrderPreIntegrationTable.h"

#include "vtkFloatArray.h"
#include "vtkObjectFactory.h"
#include "vtkSMPTools.h"
#include "vtkSecondOrderPreIntegrationTableKernel.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <vector>

vtkStandardNewMacro(vtkSecondOrderPreIntegrationTable);

//------------------------------------------------------------------------------
vtkSecondOrderPreIntegrationTable::vtkSecondOrderPreIntegrationTable()
  : IterationTable(vtkFloatArray::New())
  , IterationEmptyRuns(vtkFloatArray::New())
  , BuiltIterationTable(vtkFloatArray::New())
{
  this->IterationTable->SetNumberOfComponents(4);
  this->BuiltIterationTable->SetNumberOfComponents(4);
  this->SegmentLength = 2.0;
}

//------------------------------------------------------------------------------
vtkSecondOrderPreIntegrationTable::~vtkSecondOrderPreIntegrationTable()
{
  this->IterationTable->Delete();
  this->IterationEmptyRuns->Delete();
  this->BuiltIterationTable->Delete();
}

//------------------------------------------------------------------------------
bool vtkSecondOrderPreIntegrationTable::AdoptBuild(vtkPreIntegrationTable* built)
{
  auto* other = vtkSecondOrderPreIntegrationTable::SafeDownCast(built);
  if (!other || other->ChordSize != this->ChordSize ||
    other->GetEffectiveChordRange() != this->GetEffectiveChordRange() ||
    other->DeviationSize != this->DeviationSize ||
    other->GetEffectiveDeviationRange() != this->GetEffectiveDeviationRange() ||
    other->Iterations != this->Iterations || other->Prefilter != this->Prefilter ||
    other->Moments != this->Moments || other->SlabMoments != this->SlabMoments ||
    !this->Superclass::AdoptBuild(built))
  {
    return false;
  }
  std::swap(this->IterationTable, other->IterationTable);
  std::swap(this->IterationEmptyRuns, other->IterationEmptyRuns);
  this->IterationSamples = other->IterationSamples;
  this->IterationSamplesPerSpacing = other->IterationSamplesPerSpacing;
  // The entries taken are this kernel's: the next edit rebuilds only what it reaches.
  this->BuiltIterationTable->DeepCopy(this->IterationTable);
  this->BuiltKernel = this->GetKernel();
  this->BuiltLayers = this->GetNumberOfLayers();
  this->BuiltEntries = this->GetNumberOfEntries();
  this->BuiltValid = this->ComputeEntries;
  this->DirtySamples[0] = 0;
  this->DirtySamples[1] = -1;
  this->LastBuildEntries = other->LastBuildEntries;
  this->LastBuildCentres[0] = 0;
  this->LastBuildCentres[1] = this->TableSize - 1;
  other->BuiltValid = false;
  return true;
}

//------------------------------------------------------------------------------
bool vtkSecondOrderPreIntegrationTable::TakeEntries(vtkSecondOrderPreIntegrationTable* other)
{
  if (!other || other == this || !other->BuiltValid || !other->ComputeEntries ||
    !other->Sampler->Prepare())
  {
    return false;
  }
  other->BuildIterationTable();
  if (!other->BuiltKernel.SameAs(other->GetKernel()) ||
    other->BuiltLayers != other->GetNumberOfLayers() ||
    other->BuiltEntries != other->GetNumberOfEntries() ||
    other->Table->GetNumberOfTuples() != other->BuiltEntries)
  {
    return false;
  }
  std::swap(this->Table, other->Table);
  std::swap(this->BuiltIterationTable, other->BuiltIterationTable);
  this->BuiltKernel = other->BuiltKernel;
  this->BuiltLayers = other->BuiltLayers;
  this->BuiltEntries = other->BuiltEntries;
  this->DirtySamples[0] = other->DirtySamples[0];
  this->DirtySamples[1] = other->DirtySamples[1];
  this->BuiltValid = true;
  // Other keeps no entries: its key no longer describes its table.
  other->Table->Initialize();
  other->Table->SetNumberOfComponents(4);
  other->BuildKey.clear();
  other->BuiltValid = false;
  other->Modified();
  return true;
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::AppendBuildKey(std::vector<double>& key) const
{
  this->Superclass::AppendBuildKey(key);
  key.insert(key.end(),
    { static_cast<double>(this->ChordSize),
      this->GetEffectiveChordRange(),
      static_cast<double>(this->DeviationSize),
      this->GetEffectiveDeviationRange(),
      static_cast<double>(this->Iterations),
      this->Prefilter ? 1.0 : 0.0,
      static_cast<double>(this->Moments),
      static_cast<double>(this->SlabMoments) });
}

//------------------------------------------------------------------------------
vtkIdType vtkSecondOrderPreIntegrationTable::GetNumberOfEntries() const
{
  return static_cast<vtkIdType>(this->TableSize) * this->ChordSize * this->DeviationSize *
    this->GetNumberOfLayers();
}

//------------------------------------------------------------------------------
int vtkSecondOrderPreIntegrationTable::GetNumberOfLayers() const
{
  return this->DeviationSize == 1 ? std::max(this->Moments, 1)
                                  : (this->SlabMoments > 0 ? 2 * this->SlabMoments : 1);
}

//------------------------------------------------------------------------------
double vtkSecondOrderPreIntegrationTable::GetEffectiveChordRange() const
{
  const double width = this->ScalarRange[1] - this->ScalarRange[0];
  return this->ChordSize < 2 ? 0.0 : this->ChordRange > 0.0 ? this->ChordRange : width;
}

//------------------------------------------------------------------------------
double vtkSecondOrderPreIntegrationTable::GetEffectiveDeviationRange() const
{
  const double width = this->ScalarRange[1] - this->ScalarRange[0];
  return this->DeviationSize < 2 ? 0.0 : this->DeviationRange > 0.0 ? this->DeviationRange : width;
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::BuildIterationTable()
{
  const int n = this->TableSize;
  const double width = this->ScalarRange[1] - this->ScalarRange[0];
  const double tableSpacing = width / (n - 1);
  const double feature = this->Sampler->GetSmallestFeature();
  // At least 2 samples per centre spacing and 16 across the narrowest feature; even, so that
  // the prefilter's box ends fall on samples; at most 65537 samples in all.
  const double wanted = std::ceil(16.0 * tableSpacing / feature);
  const int p = 2 *
    static_cast<int>(
      std::max(1.0, std::min(std::ceil(0.5 * wanted), std::floor(32768.0 / (n - 1)))));
  this->IterationSamplesPerSpacing = p;
  const int fine = p * (n - 1) + 1; // entry i at sample p i
  this->IterationSamples = fine;
  const double s0 = this->ScalarRange[0];
  const double spacing = width / (fine - 1);
  // The last sample exactly at ScalarRange[1]: s0 + (fine - 1) spacing can miss it by a
  // rounding error, which matters for a transfer-function step at the range end.
  const double s1 = this->ScalarRange[1];
  const double top = fine - 1.0;
  auto scalar = [&](double x) { return x >= top ? s1 : s0 + x * spacing; };

  // Extinction-weighted colour and extinction at the samples, and (prefiltered) their box
  // averages over one centre spacing.
  std::vector<double> point(4 * static_cast<size_t>(fine));
  for (int q = 0; q < fine; ++q)
  {
    double rgbTau[4];
    this->Sampler->Evaluate(scalar(q), rgbTau);
    for (int c = 0; c < 3; ++c)
    {
      point[4 * q + c] = rgbTau[c] * rgbTau[3];
    }
    point[4 * q + 3] = rgbTau[3];
  }
  // Half a centre spacing, in samples: the half-width of the box filter.
  const int halfWidth = this->Prefilter ? p / 2 : 0;
  std::vector<double> filtered;
  if (this->Prefilter)
  {
    // Integral from sample 0 to each sample, by Simpson's rule on Panels panels per spacing:
    // the extinction curves sharply where the opacity nears 1 and kinks at the transfer
    // function's nodes, which the samples alone would integrate coarsely.
    constexpr int Panels = 4;
    std::vector<double> integral(4 * static_cast<size_t>(fine), 0.0);
    for (int q = 1; q < fine; ++q)
    {
      double sum[4] = { 0.0, 0.0, 0.0, 0.0 };
      for (int m = 0; m <= 2 * Panels; ++m)
      {
        const double weight = m == 0 || m == 2 * Panels ? 1.0 : m % 2 ? 4.0 : 2.0;
        double value[4];
        if (m == 0 || m == 2 * Panels)
        {
          std::copy(&point[4 * (m == 0 ? q - 1 : q)], &point[4 * (m == 0 ? q - 1 : q)] + 4, value);
        }
        else
        {
          double rgbTau[4];
          this->Sampler->Evaluate(scalar(q - 1 + 0.5 * m / Panels), rgbTau);
          for (int c = 0; c < 3; ++c)
          {
            value[c] = rgbTau[c] * rgbTau[3];
          }
          value[3] = rgbTau[3];
        }
        for (int c = 0; c < 4; ++c)
        {
          sum[c] += weight * value[c];
        }
      }
      for (int c = 0; c < 4; ++c)
      {
        integral[4 * q + c] = integral[4 * (q - 1) + c] + sum[c] / (6.0 * Panels);
      }
    }
    filtered.resize(point.size());
    for (int q = 0; q < fine; ++q)
    {
      // Centred, and narrowing to nothing at the range ends: data exactly at an end (often
      // saturated or clamped values) keeps that end's exact transfer function.
      const int h = std::min(halfWidth, std::min(q, fine - 1 - q));
      for (int c = 0; c < 4; ++c)
      {
        filtered[4 * q + c] = h > 0
          ? (integral[4 * (q + h) + c] - integral[4 * (q - h) + c]) / (2.0 * h)
          : point[4 * q + c];
      }
    }
  }
  const std::vector<double>& values = this->Prefilter ? filtered : point;
  this->IterationTable->SetNumberOfTuples(fine);
  float* samples = this->IterationTable->GetPointer(0);
  for (size_t v = 0; v < values.size(); ++v)
  {
    samples[v] = static_cast<float>(values[v]);
  }

  // Zero-opacity runs of the (filtered) iteration table: a spacing is empty when the transfer
  // function has no opacity within half a centre spacing of it.
  this->IterationEmptyRuns->SetNumberOfTuples(fine - 1);
  int run = -1;
  bool inRun = false;
  for (int q = 0; q < fine - 1; ++q)
  {
    const bool empty = this->Sampler->GetMaximumOpacity(scalar(std::max(q - halfWidth, 0)),
                         scalar(std::min(q + 1 + halfWidth, fine - 1))) <= 0.0;
    run += empty && !inRun ? 1 : 0;
    inRun = empty;
    this->IterationEmptyRuns->SetValue(q, empty ? static_cast<float>(run) : -1.0f);
  }
}

//------------------------------------------------------------------------------
vtkSecondOrderPreIntegrationTableKernel vtkSecondOrderPreIntegrationTable::GetKernel() const
{
  vtkSecondOrderPreIntegrationTableKernel kernel;
  const double width = this->ScalarRange[1] - this->ScalarRange[0];
  const double spacing = width / (this->IterationSamples - 1);
  kernel.SamplesPerSpacing = this->IterationSamplesPerSpacing;
  kernel.Samples = this->IterationSamples;
  kernel.ChordSize = this->ChordSize;
  kernel.DeviationSize = this->DeviationSize;
  kernel.ChordHalfStep = this->ChordSize < 2
    ? 0.0f
    : static_cast<float>(this->GetEffectiveChordRange() / spacing / (this->ChordSize - 1));
  kernel.DeviationHalfStep = this->DeviationSize < 2
    ? 0.0f
    : static_cast<float>(this->GetEffectiveDeviationRange() / spacing / (this->DeviationSize - 1));
  kernel.MaximumSteps = this->Iterations;
  kernel.Length = static_cast<float>(this->SegmentLength);
  return kernel;
}

//------------------------------------------------------------------------------
bool vtkSecondOrderPreIntegrationTable::ChangedSamples(
  const vtkSecondOrderPreIntegrationTableKernel& kernel,
  int& first,
  int& last) const
{
  if (!kernel.SameAs(this->BuiltKernel) || this->GetNumberOfLayers() != this->BuiltLayers ||
    this->GetNumberOfEntries() != this->BuiltEntries ||
    this->BuiltIterationTable->GetNumberOfTuples() != this->IterationSamples)
  {
    return false;
  }
  vtkSecondOrderPreIntegrationTableKernel::ChangedSamples(this->BuiltIterationTable->GetPointer(0),
    this->IterationTable->GetPointer(0),
    this->IterationSamples,
    first,
    last);
  if (this->DirtySamples[1] >= this->DirtySamples[0])
  {
    // One range holds both: Reads() tests a path against a single range.
    first = last < first ? this->DirtySamples[0] : std::min(first, this->DirtySamples[0]);
    last = std::max(last, this->DirtySamples[1]);
  }
  return true;
}

//------------------------------------------------------------------------------
vtkIdType vtkSecondOrderPreIntegrationTable::GetNumberOfEntriesToBuild()
{
  const vtkIdType entries = this->GetNumberOfEntries();
  if (!this->ComputeEntries || !this->BuiltValid || !this->Sampler->Prepare())
  {
    return entries;
  }
  this->BuildIterationTable();
  const vtkSecondOrderPreIntegrationTableKernel kernel = this->GetKernel();
  int first, last;
  if (!this->ChangedSamples(kernel, first, last))
  {
    return entries;
  }
  // As BuildTable() walks them: chord j and its mirror share a path.
  const int nc = this->TableSize, nb = this->ChordSize, nd = this->DeviationSize;
  std::atomic<vtkIdType> count{ 0 };
  vtkSMPTools::For(0,
    static_cast<vtkIdType>(nd) * nc,
    [&](vtkIdType begin, vtkIdType end)
    {
      vtkIdType local = 0;
      for (vtkIdType row = begin; row < end; ++row)
      {
        const int i = static_cast<int>(row % nc), k = static_cast<int>(row / nc);
        for (int j = 0; j <= (nb - 1) / 2; ++j)
        {
          if (kernel.Reads(i, j, k, first, last))
          {
            local += nb - 1 - j != j ? 2 : 1;
          }
        }
      }
      count += local;
    });
  return count;
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::BuildTable()
{
  this->BuildIterationTable();
  const bool wasValid = this->BuiltValid;
  this->BuiltValid = false;
  this->LastBuildEntries = 0;
  this->LastBuildCentres[0] = 0;
  this->LastBuildCentres[1] = this->TableSize - 1;
  if (!this->ComputeEntries)
  {
    return; // another builder (the GPU) integrates from the iteration table
  }
  const vtkSecondOrderPreIntegrationTableKernel kernel = this->GetKernel();
  // After an edit of the transfer functions alone (the same kernel, layers and entries, the
  // table still holding the last build), only the entries that read a changed sample are
  // integrated: [changedFirst, changedLast] are the samples that differ.
  int changedFirst = 0, changedLast = this->IterationSamples - 1;
  const vtkIdType entries = this->GetNumberOfEntries();
  const bool incremental = wasValid && this->ChangedSamples(kernel, changedFirst, changedLast);
  // Nothing changed at all: the entries, the iteration table and its empty runs (built from
  // the same samples) are the last build's.
  this->EntriesUnchanged = incremental && changedLast < changedFirst;
  this->BuiltKernel = kernel;
  this->BuiltLayers = this->GetNumberOfLayers();
  this->BuiltEntries = entries;
  const float* samples = this->IterationTable->GetPointer(0);
  const float* runs = this->IterationEmptyRuns->GetPointer(0);
  float* table = this->Table->GetPointer(0);
  const int nc = this->TableSize, nb = this->ChordSize, nd = this->DeviationSize;
  // Shaded tables hold moment layers (first order: Moments, nd = 1; second order: the
  // SlabMoments of both halves of every slab), one layer stride apart.
  const bool firstOrderMoments = this->Moments > 0 && nd == 1;
  const bool slabMoments = this->SlabMoments > 0 && nd > 1;
  const int layers = slabMoments ? this->SlabMoments : this->Moments;
  const size_t stride = 4 * static_cast<size_t>(nc) * nb * nd;
  // A task per (deviation, centre) row of chords: its pairs (j, nb - 1 - j) share their
  // iteration-table lookups.
  std::atomic<vtkIdType> integrated{ 0 };
  std::mutex centresMutex;
  int centres[2] = { nc, -1 }; // the centre entries integrated
  const bool complete = this->ForInParts(static_cast<vtkIdType>(nd) * nc,
    [&](vtkIdType begin, vtkIdType end)
    {
      std::vector<float> steps;
      vtkIdType count = 0;
      int lowest = nc, highest = -1;
      for (vtkIdType row = begin; row < end; ++row)
      {
        const int i = static_cast<int>(row % nc), k = static_cast<int>(row / nc);
        for (int j = 0; j <= (nb - 1) / 2; ++j)
        {
          if (incremental && !kernel.Reads(i, j, k, changedFirst, changedLast))
          {
            continue; // reads no changed sample: its value stands
          }
          const int mirror = nb - 1 - j;
          count += mirror != j ? 2 : 1;
          lowest = std::min(lowest, i);
          highest = std::max(highest, i);
          float* forward = table + 4 * (i + static_cast<vtkIdType>(nc) * (j + nb * k));
          float* backward = mirror != j
            ? table + 4 * (i + static_cast<vtkIdType>(nc) * (mirror + nb * k))
            : nullptr;
          if (firstOrderMoments || slabMoments)
          {
            kernel.IntegrateMoments(
              i, j, k, slabMoments, samples, runs, steps, layers, stride, forward, backward);
          }
          else
          {
            kernel.Integrate(i, j, k, samples, runs, steps, forward, backward);
          }
        }
      }
      integrated += count;
      std::lock_guard<std::mutex> lock(centresMutex);
      centres[0] = std::min(centres[0], lowest);
      centres[1] = std::max(centres[1], highest);
    });
  this->LastBuildEntries = integrated * this->GetNumberOfLayers();
  this->LastBuildCentres[0] = complete ? centres[0] : 0;
  this->LastBuildCentres[1] = complete ? centres[1] : nc - 1;
  if (complete)
  {
    this->BuiltIterationTable->DeepCopy(this->IterationTable);
    this->DirtySamples[0] = 0;
    this->DirtySamples[1] = -1;
  }
  else if (incremental)
  {
    // Stopped part way: an entry that reads none of the changed samples still holds the
    // value of the samples last built from (and of the new ones); the others may hold either.
    this->DirtySamples[0] = changedFirst;
    this->DirtySamples[1] = changedLast;
  }
  this->BuiltValid = complete || incremental;
}

//------------------------------------------------------------------------------
double vtkSecondOrderPreIntegrationTable::GetEmptyRunMargin() const
{
  return this->Prefilter
    ? 0.5 * (this->ScalarRange[1] - this->ScalarRange[0]) / (this->TableSize - 1)
    : 0.0;
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::GetEntryPath(int i, int j, int k, double path[3]) const
{
  const double width = this->ScalarRange[1] - this->ScalarRange[0];
  const double c = i == this->TableSize - 1
    ? this->ScalarRange[1]
    : this->ScalarRange[0] + width * i / (this->TableSize - 1);
  const double chord = this->ChordSize < 2
    ? 0.0
    : this->GetEffectiveChordRange() * (2.0 * j - (this->ChordSize - 1)) / (this->ChordSize - 1);
  const double deviation = this->DeviationSize < 2 ? 0.0
                                                   : this->GetEffectiveDeviationRange() *
      (2.0 * k - (this->DeviationSize - 1)) / (this->DeviationSize - 1);
  path[0] = c - 0.5 * chord;
  path[1] = chord + 4.0 * deviation;
  path[2] = -4.0 * deviation;
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::GetEntry(int i, int j, int k, double rgba[4])
{
  const vtkIdType index =
    i + static_cast<vtkIdType>(this->TableSize) * (j + static_cast<vtkIdType>(this->ChordSize) * k);
  for (int c = 0; c < 4; ++c)
  {
    rgba[c] = this->Table->GetTypedComponent(index, c);
  }
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ChordSize: " << this->ChordSize << "\n";
  os << indent << "ChordRange: " << this->ChordRange << "\n";
  os << indent << "DeviationSize: " << this->DeviationSize << "\n";
  os << indent << "DeviationRange: " << this->DeviationRange << "\n";
  os << indent << "Iterations: " << this->Iterations << "\n";
  os << indent << "Prefilter: " << (this->Prefilter ? "On" : "Off") << "\n";
  os << indent << "Moments: " << this->Moments << "\n";
  os << indent << "SlabMoments: " << this->SlabMoments << "\n";
}
