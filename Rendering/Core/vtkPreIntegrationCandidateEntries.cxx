// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkPreIntegrationCandidateEntries.h"

#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkSMPTools.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <cmath>
#include <new>
#include <thread>

// Zeroed memory is a valid array of these atomics holding 0 (a lock-free byte).
static_assert(
  sizeof(std::atomic<unsigned char>) == 1 && std::atomic<unsigned char>::is_always_lock_free,
  "the entry states must be lock-free bytes");

//------------------------------------------------------------------------------
vtkPreIntegrationCandidateEntries::vtkPreIntegrationCandidateEntries()
  : States(nullptr, &std::free)
{
}

//------------------------------------------------------------------------------
vtkPreIntegrationCandidateEntries::~vtkPreIntegrationCandidateEntries() = default;

//------------------------------------------------------------------------------
bool vtkPreIntegrationCandidateEntries::Allocate(vtkSecondOrderPreIntegrationTable* settings,
  bool prefilter,
  int tableSize,
  int chordSize,
  double chordRange,
  int deviationSize,
  double deviationRange)
{
  this->Values.reset();
  this->States.reset();
  vtkSecondOrderPreIntegrationTable* table = this->Table;
  table->GetSampler()->SetFromSampler(settings->GetSampler());
  table->SetScalarRange(settings->GetScalarRange());
  table->SetSegmentLength(settings->GetSegmentLength());
  table->SetIterations(settings->GetIterations());
  table->SetPrefilter(prefilter);
  table->SetTableSize(tableSize);
  table->SetChordSize(chordSize);
  table->SetDeviationSize(deviationSize);
  table->SetChordRange(chordRange);
  table->SetDeviationRange(deviationRange);
  if (!table->GetSampler()->Prepare())
  {
    return false;
  }
  table->BuildIterationTable();
  const vtkIdType entries = table->GetNumberOfEntries();
  this->Values.reset(new (std::nothrow) float[4 * static_cast<size_t>(entries)]);
  this->States.reset(static_cast<std::atomic<unsigned char>*>(
    std::calloc(entries, sizeof(std::atomic<unsigned char>))));
  if (!this->Values || !this->States)
  {
    this->Values.reset();
    this->States.reset();
    return false;
  }
  this->Kernel = table->GetKernel();
  this->Samples = table->GetIterationTable()->GetPointer(0);
  this->Runs = table->GetIterationEmptyRuns()->GetPointer(0);
  const double* range = table->GetScalarRange();
  std::copy(range, range + 2, this->Range);
  const double extents[2] = { table->GetEffectiveChordRange(),
    table->GetEffectiveDeviationRange() };
  const int sizes[3] = { tableSize, chordSize, deviationSize };
  for (int a = 0; a < 3; ++a)
  {
    this->Size[a] = sizes[a];
    this->Low[a] = a == 0 ? range[0] : -extents[a - 1];
    const double span = a == 0 ? range[1] - range[0] : 2.0 * extents[a - 1];
    this->Spacing[a] = sizes[a] > 1 ? span / (sizes[a] - 1) : 0.0;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationCandidateEntries::Update(vtkSecondOrderPreIntegrationTable* settings,
  bool prefilter,
  int tableSize,
  int chordSize,
  double chordRange,
  int deviationSize,
  double deviationRange)
{
  vtkSecondOrderPreIntegrationTable* table = this->Table;
  const double* range = settings->GetScalarRange();
  const double* own = table->GetScalarRange();
  if (!this->Values || table->GetPrefilter() != prefilter || table->GetTableSize() != tableSize ||
    table->GetChordSize() != chordSize || table->GetChordRange() != chordRange ||
    table->GetDeviationSize() != deviationSize || table->GetDeviationRange() != deviationRange ||
    own[0] != range[0] || own[1] != range[1] ||
    table->GetSegmentLength() != settings->GetSegmentLength() ||
    table->GetIterations() != settings->GetIterations())
  {
    return false;
  }
  vtkNew<vtkVolumeTransferFunctionSampler> sampler;
  sampler->SetFromSampler(settings->GetSampler());
  if (!sampler->Prepare())
  {
    return false;
  }
  if (sampler->GetContentHash() == table->GetSampler()->GetContentHash())
  {
    return true; // the same transfer functions: every entry stands
  }
  // The new iteration table, compared with the one the entries were integrated from.
  const std::vector<float> before(this->Samples, this->Samples + 4 * this->Kernel.Samples);
  table->GetSampler()->SetFromSampler(sampler);
  table->GetSampler()->Prepare();
  table->BuildIterationTable();
  const vtkSecondOrderPreIntegrationTableKernel kernel = table->GetKernel();
  this->Samples = table->GetIterationTable()->GetPointer(0);
  this->Runs = table->GetIterationEmptyRuns()->GetPointer(0);
  if (!kernel.SameAs(this->Kernel))
  {
    this->Values.reset(); // integrated from another resolution: none can be kept
    this->States.reset();
    return false;
  }
  int first, last;
  vtkSecondOrderPreIntegrationTableKernel::ChangedSamples(
    before.data(), this->Samples, kernel.Samples, first, last);
  if (last < first)
  {
    return true;
  }
  // Forget the integrated entries whose paths read a changed sample (and the next one up).
  const int nc = this->Size[0], nb = this->Size[1];
  const vtkIdType entries = static_cast<vtkIdType>(nc) * nb * this->Size[2];
  std::atomic<unsigned char>* states = this->States.get();
  vtkSMPTools::For(0,
    entries,
    [&](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType index = begin; index < end; ++index)
      {
        if (states[index].load(std::memory_order_relaxed) == 0)
        {
          continue;
        }
        const int i = static_cast<int>(index % nc);
        const int j = static_cast<int>((index / nc) % nb);
        const int k = static_cast<int>(index / (static_cast<vtkIdType>(nc) * nb));
        if (kernel.Reads(i, std::min(j, nb - 1 - j), k, first, last)) // as Ensure() integrates
        {
          states[index].store(0, std::memory_order_relaxed);
        }
      }
    });
  return true;
}

//------------------------------------------------------------------------------
double vtkPreIntegrationCandidateEntries::GetReservedBytes() const
{
  const double entries = static_cast<double>(this->Size[0]) * this->Size[1] * this->Size[2];
  return this->Values ? 17.0 * entries : 0.0;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationCandidateEntries::MakeLookup(int tableSize,
  int chordSize,
  double chordRange,
  int deviationSize,
  double deviationRange,
  Lookup& lookup) const
{
  if (!this->Values || tableSize != this->Size[0])
  {
    return false;
  }
  const double* range = this->Range;
  vtkPreIntegrationRayMarch::TableView& view = lookup.View;
  view.Entries = nullptr;
  view.Dimensions = 3;
  view.Chords = true;
  view.Size[0] = tableSize;
  view.Low[0] = range[0];
  view.ToIndex[0] = (tableSize - 1) / (range[1] - range[0]);
  lookup.Offset[0] = 0;
  lookup.Scale[0] = 1;
  const int sizes[2] = { chordSize, deviationSize };
  const double extents[2] = { sizes[0] > 1 ? chordRange : 0.0,
    sizes[1] > 1 ? deviationRange : 0.0 };
  for (int a = 1; a < 3; ++a)
  {
    const int n = sizes[a - 1];
    const double extent = extents[a - 1];
    view.Size[a] = n;
    view.Low[a] = -extent;
    view.ToIndex[a] = n > 1 && extent > 0.0 ? (n - 1) / (2.0 * extent) : 0.0;
    // The candidate's entries must be the store's: its spacing a whole multiple of the
    // store's, its lowest entry on the store's grid, its highest inside it.
    const double spacing = n > 1 ? 2.0 * extent / (n - 1) : 0.0;
    if (n == 1)
    {
      if (this->Size[a] % 2 == 0)
      {
        return false; // no store entry at 0
      }
      lookup.Offset[a] = this->Size[a] / 2;
      lookup.Scale[a] = 1;
      continue;
    }
    if (!(this->Spacing[a] > 0.0))
    {
      return false;
    }
    const double ratio = spacing / this->Spacing[a];
    const double scale = std::round(ratio);
    const double offset = std::round((-extent - this->Low[a]) / this->Spacing[a]);
    if (scale < 1.0 || std::abs(ratio - scale) > 1e-9 * scale ||
      std::abs((-extent - this->Low[a]) / this->Spacing[a] - offset) > 1e-6 || offset < 0.0 ||
      offset + scale * (n - 1) > this->Size[a] - 1)
    {
      return false;
    }
    lookup.Offset[a] = static_cast<int>(offset);
    lookup.Scale[a] = static_cast<int>(scale);
  }
  lookup.Store = this;
  return true;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationCandidateEntries::Ensure(vtkIdType index, std::vector<float>& steps) const
{
  std::atomic<unsigned char>& state = this->States.get()[index];
  if (state.load(std::memory_order_acquire) == 2)
  {
    return;
  }
  unsigned char expected = 0; // 0: not integrated, 1: being integrated, 2: ready
  if (state.compare_exchange_strong(expected, 1, std::memory_order_acq_rel))
  {
    const int nc = this->Size[0], nb = this->Size[1];
    const int i = static_cast<int>(index % nc);
    const int j = static_cast<int>((index / nc) % nb);
    const int k = static_cast<int>(index / (static_cast<vtkIdType>(nc) * nb));
    const int mirror = nb - 1 - j;
    float forward[4];
    float* entry = this->Values.get() + 4 * index;
    // As the builder: chord j > mirror is the reversed path of the mirror's.
    if (j <= mirror)
    {
      this->Kernel.Integrate(i, j, k, this->Samples, this->Runs, steps, entry, nullptr);
    }
    else
    {
      this->Kernel.Integrate(i, mirror, k, this->Samples, this->Runs, steps, forward, entry);
    }
    state.store(2, std::memory_order_release);
    return;
  }
  while (state.load(std::memory_order_acquire) != 2)
  {
    std::this_thread::yield();
  }
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationCandidateEntries::IsEmptyBetween(double low, double high) const
{
  if (!this->Runs || !(this->Spacing[0] > 0.0) || !(low <= high))
  {
    return false;
  }
  // Kernel units: centre entry i lies at sample SamplesPerSpacing i.
  const double unit = this->Spacing[0] / this->Kernel.SamplesPerSpacing;
  const double top = this->Kernel.Samples - 1;
  const double lo = std::min(std::max((low - this->Range[0]) / unit - 1.0, 0.0), top);
  const double hi = std::min(std::max((high - this->Range[0]) / unit + 1.0, 0.0), top);
  const int qlo = std::min(static_cast<int>(lo), this->Kernel.Samples - 2);
  const int qhi = std::min(static_cast<int>(hi), this->Kernel.Samples - 2);
  // Runs are numbered in order, so equal numbers at both ends hold one run between them.
  return this->Runs[qlo] >= 0.0f && this->Runs[qlo] == this->Runs[qhi];
}

//------------------------------------------------------------------------------
void vtkPreIntegrationCandidateEntries::Lookup::Read(const double v[3],
  double fraction,
  double rgba[4]) const
{
  // The interpolation cell in the candidate's axes (TableView::Corners), its corners in the
  // store's: per axis the store offsets and weights of the cell's two sides, combined as the
  // corners c = 0..7 (bit a of c: side along axis a), the weights multiplied in axis order.
  const int* size = this->Store->Size;
  vtkIdType sides[3][2];
  double weights[3][2];
  vtkIdType stride = 1;
  for (int a = 0; a < 3; ++a)
  {
    const double x = this->View.Index(a, v[a]);
    const int cell = std::min(static_cast<int>(x), std::max(this->View.Size[a] - 2, 0));
    const double w = x - cell;
    const int next = cell + (this->View.Size[a] > 1 ? 1 : 0);
    sides[a][0] = (this->Offset[a] + this->Scale[a] * cell) * stride;
    sides[a][1] = (this->Offset[a] + this->Scale[a] * next) * stride;
    weights[a][0] = 1.0 - w;
    weights[a][1] = w;
    stride *= size[a];
  }
  const float* values = this->Store->Values.get();
  const std::atomic<unsigned char>* states = this->Store->States.get();
  std::fill(rgba, rgba + 4, 0.0);
  for (int c = 0; c < 8; ++c)
  {
    const int b0 = c & 1, b1 = (c >> 1) & 1, b2 = (c >> 2) & 1;
    const double product = weights[0][b0] * weights[1][b1] * weights[2][b2];
    const vtkIdType offset = sides[0][b0] + sides[1][b1] + sides[2][b2];
    if (states[offset].load(std::memory_order_acquire) != 2)
    {
      this->Store->Ensure(offset, this->Steps);
    }
    const float* e = values + 4 * offset;
    for (int k = 0; k < 4; ++k)
    {
      rgba[k] += product * e[k];
    }
  }
  vtkPreIntegrationRayMarch::Scale(rgba, fraction);
}
