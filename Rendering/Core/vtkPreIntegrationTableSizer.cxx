// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkPreIntegrationTableSizer.h"

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLowPriorityThreads.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPreIntegrationCandidateEntries.h"
#include "vtkPreIntegrationRayMarch.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkTimerLog.h"
#include "vtkVolumeImageAlgorithm.h"
#include "vtkVolumeReferenceIntegrator.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

vtkStandardNewMacro(vtkPreIntegrationTableSizer);

namespace
{
using March = vtkPreIntegrationRayMarch;

struct Candidate
{
  int Sizes[3];
  double Ranges[2]; // chord and deviation extents
  bool Prefilter;
  double Error;
  double Memory;
  std::vector<double> PerRay; // squared errors of the rays
  bool Dropped;               // by the screening rays: measured on them alone, never chosen
};

// The random rays: index-space origin, direction, and interval inside the box.
struct Ray
{
  double O[3], V[3], T0, T1;
};

// One piece of a prepared ray as the shader composites it: its table axes (chord centre,
// chord, deviation of the middle sample; 0 for a segment) and its length as a fraction of a
// whole segment or slab. Pieces with a NaN sample add nothing and are not kept.
struct Piece
{
  float Axes[3];
  float Fraction;
};

// Records the pieces of one ray; composites nothing, so the ray runs to its exit.
struct RecordPieces
{
  std::vector<Piece>* Out;
  void Add(double c, double chord, double deviation, double fraction) const
  {
    this->Out->push_back(
      { { static_cast<float>(c), static_cast<float>(chord), static_cast<float>(deviation) },
        static_cast<float>(fraction) });
  }
  void Segment(double sf, double sb, double fraction, double, double rgba[4]) const
  {
    this->Add(0.5 * (sf + sb), sb - sf, 0.0, fraction);
    std::fill(rgba, rgba + 4, 0.0);
  }
  void Slab(double sf, double sm, double sb, double fraction, double, double rgba[4]) const
  {
    double v[3];
    March::TableView::SlabAxes(sf, sm, sb, v);
    this->Add(v[0], v[1], v[2], fraction);
    std::fill(rgba, rgba + 4, 0.0);
  }
};

// The exact segment model of a kept piece: its model scalar path (Eq. 2 for a slab) integrated
// through the transfer function, no table.
struct ExactLookup
{
  March::ExactPieces Exact;
  int Order = 1;
  double Step = 1.0;
  // The scalars the integration of a piece of axes v reads the transfer functions at
  // (ExactPieces::Reach of its path, as Read() makes it).
  void Reach(const float v[3], double reach[2]) const
  {
    const double sf = v[0] - 0.5 * double(v[1]), sb = v[0] + 0.5 * double(v[1]);
    double b = sb - sf, a = 0.0;
    if (this->Order == 2)
    {
      March::ExactPieces::SlabPath(sf, double(v[0]) + v[2], sb, b, a);
    }
    this->Exact.Reach(sf, b, a, reach);
  }
  void Read(const double v[3], double fraction, double rgba[4]) const
  {
    const double sf = v[0] - 0.5 * v[1], sb = v[0] + 0.5 * v[1];
    if (this->Order == 1)
    {
      this->Exact.Segment(sf, sb, fraction, this->Step, rgba);
    }
    else
    {
      this->Exact.Slab(sf, v[0] + v[2], sb, fraction, 2.0 * this->Step, rgba);
    }
  }
};

}

struct vtkPreIntegrationTableSizer::vtkInternals
{
  std::vector<Candidate> Candidates;
  std::vector<Ray> Rays;
  std::vector<double> Reference;
  March::Grid Grid;
  int Order = 2;
  double Step = 1.0;
  double Threshold = 1.0;
  vtkSecondOrderPreIntegrationTable* Table = nullptr; // the prepared one
  vtkPreIntegrationCandidateEntries Entries;          // of a candidate measured alone
  std::vector<double> LastPerRay;                     // of the last Measure()
  std::vector<double> RayKey;                         // what the rays were computed from
  std::vector<double> ReferenceKey;                   // what their reference was computed from
  // The reference's cells along each ray, kept for the transfer functions of CellSampler (a
  // copy) and the rays, range and tolerance of CellKey: an edit integrates again only the
  // cells it reaches (vtkVolumeReferenceIntegrator::RayCells).
  vtkVolumeReferenceIntegrator::RayCells Cells;
  std::vector<double> CellKey;
  vtkNew<vtkVolumeTransferFunctionSampler> CellSampler;
  // The pieces of every ray (ray r's from PieceStart[r] to PieceStart[r + 1]): they depend on
  // the volume, the rays, the order and the step, not on the transfer functions, and are kept
  // while those stay the same.
  std::vector<Piece> Pieces;
  std::vector<size_t> PieceStart;
  std::vector<double> PieceKey;
  double MeasuredChordRange = 0.0;
  double MeasuredDeviationRange = 0.0;
  std::vector<double> ExactPerRay; // the exact segment model's squared errors, when measured
  // The exact segment model's value of each piece (4 per piece), valid where ExactValid is set
  // for the transfer functions of ExactSampler (a copy) and the pieces, tolerance and range of
  // ExactKey: an edit of the transfer functions integrates again only the pieces whose reach
  // meets the scalars it changed (vtkVolumeTransferFunctionSampler::GetChangedRange).
  std::vector<double> ExactValues;
  std::vector<unsigned char> ExactValid;
  std::vector<double> ExactKey;
  vtkNew<vtkVolumeTransferFunctionSampler> ExactSampler;
  // The pieces of each ray that can read opacity through a centre size's shared store (ray
  // r's are Index[Start[r]] to Index[Start[r + 1] - 1]): every entry the others read through
  // it, for any of the centre size's candidates, is exactly zero, so leaving them out changes
  // no sum. One per prefilter; Store is null while none is made.
  struct Subset
  {
    const vtkPreIntegrationCandidateEntries* Store = nullptr;
    std::vector<uint32_t> Index;
    std::vector<size_t> Start;
  };
  Subset Subsets[2];
  // The entries the candidates of the last centre size shared in the last Choose(), kept for
  // the next one (KeepEntries).
  std::vector<std::unique_ptr<vtkPreIntegrationCandidateEntries>> Stores;
  std::atomic<bool> AbortRequested{ false };
  std::atomic<double> Progress{ 1.0 };
  bool LowPriority = false; // loops in threads of low priority

  // body(begin, end) over [0, n): with vtkSMPTools, or in threads of low priority in chunks
  // (each of which checks for an abort).
  template <class Body>
  void For(vtkIdType n, const Body& body) const
  {
    if (this->LowPriority)
    {
      vtkLowPriorityThreads::For(n, 16, body);
    }
    else
    {
      vtkSMPTools::For(0, n, body);
    }
  }
  bool Aborted = false; // the last Prepare() or Choose() stopped on AbortRequested

  // The squared errors against the reference (mean over the four channels) of rays [begin,
  // end) into perRay (rgba holding theirs; the other rays' set to 0), and their RMSE.
  double Score(const std::vector<double>& rgba,
    std::vector<double>& perRay,
    size_t begin,
    size_t end) const
  {
    perRay.assign(this->Rays.size(), 0.0);
    double total = 0.0;
    for (size_t r = begin; r < end; ++r)
    {
      double sum = 0.0;
      for (int c = 0; c < 4; ++c)
      {
        const double d = rgba[4 * (r - begin) + c] - this->Reference[4 * r + c];
        sum += d * d;
      }
      perRay[r] = 0.25 * sum;
      total += perRay[r];
    }
    return std::sqrt(total / std::max<size_t>(end - begin, 1));
  }

  // The exact segment model along the rays, each piece's value integrated unless it holds
  // from an earlier measurement (ExactValid), scored into perRay.
  double MeasureExact(const ExactLookup& exact, std::vector<double>& perRay)
  {
    const size_t rays = this->Rays.size();
    std::vector<double> rgba(4 * rays, 0.0);
    this->For(static_cast<vtkIdType>(rays),
      [&](vtkIdType begin, vtkIdType end)
      {
        for (vtkIdType r = begin; r < end && !this->AbortRequested.load(); ++r)
        {
          double* sum = &rgba[4 * r];
          for (size_t p = this->PieceStart[r]; p < this->PieceStart[r + 1]; ++p)
          {
            double* value = &this->ExactValues[4 * p];
            if (!this->ExactValid[p])
            {
              const Piece& piece = this->Pieces[p];
              const double axes[3] = { piece.Axes[0], piece.Axes[1], piece.Axes[2] };
              exact.Read(axes, piece.Fraction, value);
              this->ExactValid[p] = 1;
            }
            const double copy[4] = { value[0], value[1], value[2], value[3] };
            if (!March::Composite(copy, this->Threshold, sum))
            {
              break;
            }
          }
        }
      });
    return this->AbortRequested.load() ? -1.0 : this->Score(rgba, perRay, 0, rays);
  }

  // The subset of the pieces that can read opacity through store for candidates whose
  // axes reach at most reach[a] (their largest spacing) from a piece's value, clamped to
  // [low[a], high[a]] (the values every candidate's axis a covers: a piece beyond them reads
  // its edge entries). An entry's path x(t) = centre + chord (t - 1/2) + 4 deviation t (1 - t)
  // (Eq. 2) stays within centre -+ |chord| / 2 plus deviation's side.
  void MakeSubset(const vtkPreIntegrationCandidateEntries* store,
    const double reach[3],
    const double low[3],
    const double high[3],
    Subset& subset) const
  {
    const size_t rays = this->Rays.size();
    std::vector<std::vector<uint32_t>> perRay(rays);
    this->For(static_cast<vtkIdType>(rays),
      [&](vtkIdType begin, vtkIdType end)
      {
        for (vtkIdType r = begin; r < end; ++r)
        {
          for (size_t p = this->PieceStart[r]; p < this->PieceStart[r + 1]; ++p)
          {
            const float* v = this->Pieces[p].Axes;
            double lo[3], hi[3];
            for (int a = 0; a < 3; ++a)
            {
              lo[a] = std::min<double>(v[a], high[a]) - reach[a];
              hi[a] = std::max<double>(v[a], low[a]) + reach[a];
            }
            const double chord = 0.5 * std::max(std::abs(lo[1]), std::abs(hi[1]));
            if (!store->IsEmptyBetween(
                  lo[0] - chord + std::min(lo[2], 0.0), hi[0] + chord + std::max(hi[2], 0.0)))
            {
              perRay[r].push_back(static_cast<uint32_t>(p));
            }
          }
        }
      });
    subset.Index.clear();
    subset.Start.assign(1, 0);
    for (auto& pieces : perRay)
    {
      subset.Index.insert(subset.Index.end(), pieces.begin(), pieces.end());
      subset.Start.push_back(subset.Index.size());
    }
    subset.Store = store;
  }

  // The kept pieces of rays [first, last) (all by default, or those of subset) composited
  // with a table lookup (Read(axes, fraction, rgba)), front to back as March::Cast does,
  // scored.
  template <class Lookup>
  double MeasurePieces(const Lookup& lookup,
    std::vector<double>& perRay,
    size_t first = 0,
    size_t last = static_cast<size_t>(-1),
    const Subset* subset = nullptr) const
  {
    last = std::min(last, this->Rays.size());
    first = std::min(first, last);
    std::vector<double> rgba(4 * (last - first), 0.0);
    this->For(static_cast<vtkIdType>(last - first),
      [&](vtkIdType begin, vtkIdType end)
      {
        if (this->AbortRequested.load(std::memory_order_relaxed))
        {
          return;
        }
        const Lookup chunkLookup(lookup); // with scratch memory of its own
        for (vtkIdType k = begin; k < end; ++k)
        {
          const size_t r = first + static_cast<size_t>(k);
          double* sum = &rgba[4 * k];
          const size_t begin = subset ? subset->Start[r] : this->PieceStart[r];
          const size_t end = subset ? subset->Start[r + 1] : this->PieceStart[r + 1];
          for (size_t q = begin; q < end; ++q)
          {
            const Piece& piece = this->Pieces[subset ? subset->Index[q] : q];
            const double axes[3] = { piece.Axes[0], piece.Axes[1], piece.Axes[2] };
            double value[4];
            chunkLookup.Read(axes, piece.Fraction, value);
            if (!March::Composite(value, this->Threshold, sum))
            {
              break;
            }
          }
        }
      });
    return this->AbortRequested.load() ? -1.0 : this->Score(rgba, perRay, first, last);
  }
};

//------------------------------------------------------------------------------
vtkPreIntegrationTableSizer::vtkPreIntegrationTableSizer()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkPreIntegrationTableSizer::~vtkPreIntegrationTableSizer() = default;

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizer::CopySettings(vtkPreIntegrationTableSizer* other)
{
  if (!other || other == this)
  {
    return;
  }
  this->SetNumberOfRays(other->NumberOfRays);
  this->SetSeed(other->Seed);
  this->SetTolerance(other->Tolerance);
  this->SetMaximumMemory(other->MaximumMemory);
  this->SetBytesPerEntry(other->BytesPerEntry);
  this->SetMaximumAxisSize(other->MaximumAxisSize);
  this->SetReferenceTolerance(other->ReferenceTolerance);
  this->SetMeasureExactModel(other->MeasureExactModel);
  this->SetMeasurePrefilter(other->MeasurePrefilter);
  this->SetStopAtConvergence(other->StopAtConvergence);
  this->SetKeepEntries(other->KeepEntries);
  this->SetScreeningFraction(other->ScreeningFraction);
  this->SetOpacityThreshold(other->OpacityThreshold);
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizer::CopyStatistics(vtkPreIntegrationTableSizer* other)
{
  if (!other || other == this)
  {
    return;
  }
  this->Internals->Candidates = other->Internals->Candidates;
  this->ChosenCandidate = other->ChosenCandidate;
  this->ExactError = other->ExactError;
  this->NumberOfRaysInVolume = other->NumberOfRaysInVolume;
  this->NumberOfLevels = other->NumberOfLevels;
  this->LastChooseTime = other->LastChooseTime;
  this->MeasuredChordRange = other->MeasuredChordRange;
  this->MeasuredDeviationRange = other->MeasuredDeviationRange;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizer::SetLowPriority(bool low)
{
  if (low != this->Internals->LowPriority)
  {
    this->Internals->LowPriority = low;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizer::GetLowPriority()
{
  return this->Internals->LowPriority;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizer::ReportProgress(double progress)
{
  this->Internals->Progress = progress;
  this->InvokeEvent(vtkCommand::ProgressEvent, &progress);
}

//------------------------------------------------------------------------------
double vtkPreIntegrationTableSizer::GetProgress() const
{
  return this->Internals->Progress;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizer::Abort()
{
  this->Internals->AbortRequested = true;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizer::ClearAbort()
{
  this->Internals->AbortRequested = false;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizer::GetAborted() const
{
  return this->Internals->Aborted;
}

//------------------------------------------------------------------------------
int vtkPreIntegrationTableSizer::GetNumberOfCandidates() const
{
  return static_cast<int>(this->Internals->Candidates.size());
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizer::GetCandidateSizes(int candidate, int sizes[3]) const
{
  const auto& all = this->Internals->Candidates;
  if (candidate >= 0 && candidate < static_cast<int>(all.size()))
  {
    std::copy(all[candidate].Sizes, all[candidate].Sizes + 3, sizes);
  }
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizer::GetCandidateRanges(int candidate, double ranges[2]) const
{
  const auto& all = this->Internals->Candidates;
  if (candidate >= 0 && candidate < static_cast<int>(all.size()))
  {
    std::copy(all[candidate].Ranges, all[candidate].Ranges + 2, ranges);
  }
}

//------------------------------------------------------------------------------
double vtkPreIntegrationTableSizer::GetCandidateError(int candidate) const
{
  const auto& all = this->Internals->Candidates;
  return candidate >= 0 && candidate < static_cast<int>(all.size()) ? all[candidate].Error : 0.0;
}

//------------------------------------------------------------------------------
double vtkPreIntegrationTableSizer::GetCandidateMemory(int candidate) const
{
  const auto& all = this->Internals->Candidates;
  return candidate >= 0 && candidate < static_cast<int>(all.size()) ? all[candidate].Memory : 0.0;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizer::GetCandidatePrefilter(int candidate) const
{
  const auto& all = this->Internals->Candidates;
  return candidate >= 0 && candidate < static_cast<int>(all.size()) && all[candidate].Prefilter;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizer::GetCandidateDropped(int candidate) const
{
  const auto& all = this->Internals->Candidates;
  return candidate >= 0 && candidate < static_cast<int>(all.size()) && all[candidate].Dropped;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizer::Prepare(vtkImageData* volume,
  vtkDataArray* scalars,
  vtkSecondOrderPreIntegrationTable* table,
  int order,
  double sampleDistance)
{
  vtkInternals& I = *this->Internals;
  I.Candidates.clear();
  I.Table = nullptr;
  I.Aborted = false;
  this->ChosenCandidate = -1;
  this->ReportProgress(0.0);
  if (I.AbortRequested)
  {
    return this->Stop();
  }
  if (!table || (order != 1 && order != 2) || !(sampleDistance > 0.0) ||
    !std::isfinite(sampleDistance))
  {
    vtkErrorMacro("The sizer needs a table, order 1 or 2 and a positive, finite sample distance.");
    return false;
  }
  const std::string why = vtkVolumeImageAlgorithm::CheckVolume(volume, scalars);
  if (!why.empty())
  {
    vtkErrorMacro(<< why);
    return false;
  }
  int dims[3];
  volume->GetDimensions(dims);
  vtkVolumeTransferFunctionSampler* sampler = table->GetSampler();
  if (!sampler->Prepare())
  {
    return false;
  }
  const double* range = table->GetScalarRange();
  const double width = range[1] - range[0];
  if (!(width > 0.0) || !std::isfinite(width))
  {
    vtkErrorMacro("The table's scalar range must be finite and non-empty.");
    return false;
  }

  // The rays depend on the volume and the ray settings; their pieces also on the order and
  // the step; their ground truth on the transfer functions and the range instead. Each is
  // kept while what it depends on stays the same, so that an edit of the transfer functions
  // costs only the reference and the candidates, a change of step or order only the pieces
  // and the candidates.
  const std::vector<double> rayKey = { static_cast<double>(reinterpret_cast<uintptr_t>(volume)),
    static_cast<double>(volume->GetMTime()),
    static_cast<double>(reinterpret_cast<uintptr_t>(scalars)),
    static_cast<double>(scalars->GetMTime()),
    static_cast<double>(this->Seed),
    static_cast<double>(this->NumberOfRays) };
  std::vector<double> key = rayKey;
  // The transfer functions by content (the sampler is prepared): a copy of them, or the same
  // ones rebuilt unchanged, keeps the reference.
  key.insert(
    key.end(), { sampler->GetContentHash(), range[0], range[1], this->ReferenceTolerance });
  std::vector<double> pieceKey = rayKey;
  pieceKey.insert(pieceKey.end(), { static_cast<double>(order), sampleDistance });
  const bool reuseRays = !I.RayKey.empty() && rayKey == I.RayKey;
  const bool reuse = reuseRays && key == I.ReferenceKey;
  const bool reusePieces = reuseRays && pieceKey == I.PieceKey;
  I.ReferenceKey.clear();
  I.PieceKey.clear();
  I.RayKey.clear();

  // The volume read in place (a double copy only for arrays that cannot be), and the world
  // -> 0-based grid index map.
  if (!I.Grid.Values.SetArray(scalars))
  {
    vtkErrorMacro("Not enough memory for a double copy of the volume.");
    return false;
  }
  std::copy(dims, dims + 3, I.Grid.Dims);
  I.Order = order;
  I.Step = sampleDistance;
  I.Threshold = this->OpacityThreshold;
  vtkNew<vtkMatrix4x4> toIndex;
  toIndex->DeepCopy(volume->GetPhysicalToIndexMatrix());
  const int* extent = volume->GetExtent();
  for (int r = 0; r < 3; ++r)
  {
    toIndex->SetElement(r, 3, toIndex->GetElement(r, 3) - extent[2 * r]);
  }

  // Random rays: a uniform direction, then a uniform point of the disc through the volume's
  // centre across it (as the pixels of a parallel view), from outside the volume.
  double bounds[6];
  volume->GetBounds(bounds);
  const double centre[3] = {
    0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5])
  };
  const double radius = 0.5 * volume->GetLength();
  // The four coordinates of ray i come from a Halton sequence (bases 2, 3, 5, 7) shifted
  // modulo 1 by the seed's random offsets: evenly spread rays, whose error estimates vary
  // much less from one seed to another than independent random rays do.
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(this->Seed);
  double shift[4];
  for (double& value : shift)
  {
    random->Next();
    value = random->GetValue();
  }
  auto halton = [](int index, int base)
  {
    double value = 0.0, scale = 1.0 / base;
    for (; index > 0; index /= base, scale /= base)
    {
      value += scale * (index % base);
    }
    return value;
  };
  if (!reuseRays)
  {
    I.Rays.clear();
  }
  for (int attempt = 0; !reuseRays && attempt < 8 * this->NumberOfRays &&
       static_cast<int>(I.Rays.size()) < this->NumberOfRays;
       ++attempt)
  {
    static const int bases[4] = { 2, 3, 5, 7 };
    double u[4];
    for (int k = 0; k < 4; ++k)
    {
      u[k] = halton(attempt + 1, bases[k]) + shift[k];
      u[k] -= std::floor(u[k]);
    }
    const double z = 2.0 * u[0] - 1.0, phi = 2.0 * vtkMath::Pi() * u[1];
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double d[3] = { s * std::cos(phi), s * std::sin(phi), z };
    double e1[3], e2[3];
    vtkMath::Perpendiculars(d, e1, e2, 0.0);
    const double r = radius * std::sqrt(u[2]), theta = 2.0 * vtkMath::Pi() * u[3];
    double world[4] = { 0, 0, 0, 1 }, direction[4] = { d[0], d[1], d[2], 0 };
    for (int a = 0; a < 3; ++a)
    {
      world[a] =
        centre[a] + r * (std::cos(theta) * e1[a] + std::sin(theta) * e2[a]) - 2.0 * radius * d[a];
    }
    Ray ray;
    double o[4], v[4];
    toIndex->MultiplyPoint(world, o);
    toIndex->MultiplyPoint(direction, v);
    std::copy(o, o + 3, ray.O);
    std::copy(v, v + 3, ray.V);
    if (I.Grid.Clip(ray.O, ray.V, ray.T0, ray.T1))
    {
      I.Rays.push_back(ray);
    }
  }
  this->NumberOfRaysInVolume = static_cast<int>(I.Rays.size());
  I.RayKey = rayKey;

  // Ground truth along them, at the reference integrator's tolerance: a coarser one puts a
  // floor under the errors measured, below which no candidate can be told from another.
  const double tolerance = this->ReferenceTolerance;
  if (!reuse)
  {
    // The cells kept from the last reference hold for the same rays, range and tolerance
    // outside the scalars the edit changed; colours are kept as node weights where they
    // interpolate linearly (the same functions are a colour edit of themselves), and an edit
    // of the colours alone then changes no cell.
    std::vector<double> cellKey = rayKey;
    cellKey.insert(cellKey.end(), { range[0], range[1], tolerance });
    const int nodes = sampler->GetNumberOfColorNodes();
    const int colorNodes = nodes <= 8 && sampler->IsColorEditOf(sampler) ? nodes : 0;
    double changed[2];
    const double* edit = nullptr;
    if (reuseRays && cellKey == I.CellKey && I.Cells.ColorNodes == colorNodes &&
      I.Cells.Values.size() == I.Rays.size())
    {
      if (colorNodes > 0 && sampler->IsColorEditOf(I.CellSampler))
      {
        changed[0] = std::numeric_limits<double>::infinity();
        changed[1] = -changed[0];
      }
      else
      {
        sampler->GetChangedRange(I.CellSampler, changed);
      }
      edit = changed;
    }
    else
    {
      I.Cells.ColorNodes = colorNodes;
      I.Cells.Values.assign(I.Rays.size(), {});
      I.Cells.Kept.assign(I.Rays.size(), {});
    }
    I.CellKey.clear();
    std::vector<double> origins, directions;
    for (const Ray& ray : I.Rays)
    {
      origins.insert(origins.end(), ray.O, ray.O + 3);
      directions.insert(directions.end(), ray.V, ray.V + 3);
    }
    I.Reference.assign(4 * I.Rays.size(), 0.0);
    vtkVolumeReferenceIntegrator::IntegrateRays(I.Grid.Values,
      dims,
      sampler,
      tolerance,
      width,
      1e-7,
      static_cast<vtkIdType>(I.Rays.size()),
      origins.data(),
      directions.data(),
      I.Reference.data(),
      &I.AbortRequested,
      I.LowPriority,
      &I.Cells,
      edit);
    if (I.AbortRequested)
    {
      // Rays not yet begun hold the old values: drop them all.
      I.Cells.Values.clear();
      I.Cells.Kept.clear();
    }
    else
    {
      I.CellKey = cellKey;
      I.CellSampler->DeepCopy(sampler);
    }
  }
  if (I.AbortRequested)
  {
    return this->Stop();
  }
  I.ReferenceKey = key;
  this->ReportProgress(0.25);

  // The pieces of the rays, and the largest chord and deviation they meet.
  if (!reusePieces)
  {
    std::vector<std::vector<Piece>> perRay(I.Rays.size());
    I.For(static_cast<vtkIdType>(I.Rays.size()),
      [&](vtkIdType begin, vtkIdType end)
      {
        for (vtkIdType r = begin; r < end && !I.AbortRequested; ++r)
        {
          RecordPieces record{ &perRay[r] };
          double rgba[4];
          March::Cast(I.Grid,
            record,
            order,
            sampleDistance,
            1.0,
            I.Rays[r].O,
            I.Rays[r].V,
            I.Rays[r].T0,
            I.Rays[r].T1,
            rgba);
        }
      });
    if (I.AbortRequested)
    {
      return this->Stop();
    }
    size_t total = 0;
    for (const auto& pieces : perRay)
    {
      total += pieces.size();
    }
    I.Pieces.clear();
    I.Pieces.shrink_to_fit();
    I.Pieces.reserve(total);
    I.PieceStart.assign(1, 0);
    for (auto& pieces : perRay)
    {
      I.Pieces.insert(I.Pieces.end(), pieces.begin(), pieces.end());
      I.PieceStart.push_back(I.Pieces.size());
      std::vector<Piece>().swap(pieces);
    }
    I.MeasuredChordRange = 0.0;
    I.MeasuredDeviationRange = 0.0;
    for (const Piece& piece : I.Pieces)
    {
      I.MeasuredChordRange = std::max(I.MeasuredChordRange, std::abs(double(piece.Axes[1])));
      I.MeasuredDeviationRange =
        std::max(I.MeasuredDeviationRange, std::abs(double(piece.Axes[2])));
    }
  }
  I.PieceKey = pieceKey;
  this->ReportProgress(0.35);
  this->MeasuredChordRange = I.MeasuredChordRange;
  this->MeasuredDeviationRange = I.MeasuredDeviationRange;

  // The exact segment model: the error finer tables converge to, where the search may stop
  // (it costs about as much as the reference).
  this->ExactError = -1.0;
  I.ExactPerRay.clear();
  if (this->MeasureExactModel || this->StopAtConvergence)
  {
    ExactLookup exact;
    exact.Exact.Sampler = sampler;
    exact.Exact.Tolerance = tolerance;
    exact.Exact.DataRange = width;
    exact.Order = order;
    exact.Step = sampleDistance;
    // The pieces' values kept from the last measurement hold for the same pieces, tolerance
    // and range outside the scalars the transfer functions changed in.
    std::vector<double> exactKey = pieceKey;
    exactKey.insert(exactKey.end(), { tolerance, width });
    const size_t pieces = I.Pieces.size();
    if (exactKey != I.ExactKey || I.ExactValid.size() != pieces)
    {
      I.ExactValues.assign(4 * pieces, 0.0);
      I.ExactValid.assign(pieces, 0);
    }
    else
    {
      double changed[2];
      sampler->GetChangedRange(I.ExactSampler, changed);
      if (changed[0] <= changed[1])
      {
        I.For(static_cast<vtkIdType>(pieces),
          [&](vtkIdType begin, vtkIdType end)
          {
            for (vtkIdType p = begin; p < end; ++p)
            {
              double reach[2];
              exact.Reach(I.Pieces[p].Axes, reach);
              I.ExactValid[p] &= reach[1] < changed[0] || reach[0] > changed[1] ? 1 : 0;
            }
          });
      }
    }
    I.ExactKey = exactKey;
    I.ExactSampler->DeepCopy(sampler);
    this->ExactError = I.MeasureExact(exact, I.ExactPerRay);
    if (I.AbortRequested)
    {
      return this->Stop();
    }
  }
  I.Table = table;
  this->ReportProgress(0.45);
  return true;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizer::Stop()
{
  vtkInternals& I = *this->Internals;
  I.Aborted = true;
  I.Table = nullptr;
  for (vtkInternals::Subset& subset : I.Subsets)
  {
    subset.Store = nullptr;
  }
  I.Candidates.clear();
  I.ExactPerRay.clear();
  this->ChosenCandidate = -1;
  this->ExactError = -1.0;
  return false;
}

//------------------------------------------------------------------------------
double vtkPreIntegrationTableSizer::Measure(int tableSize,
  int chordSize,
  int deviationSize,
  double chordRange,
  double deviationRange)
{
  vtkInternals& I = *this->Internals;
  return I.Table
    ? this->MeasureCandidate(
        tableSize, chordSize, deviationSize, chordRange, deviationRange, I.Table->GetPrefilter())
    : -1.0;
}

//------------------------------------------------------------------------------
double vtkPreIntegrationTableSizer::MeasureCandidate(int tableSize,
  int chordSize,
  int deviationSize,
  double chordRange,
  double deviationRange,
  bool prefilter,
  const vtkPreIntegrationCandidateEntries* shared,
  vtkIdType begin,
  vtkIdType end)
{
  vtkInternals& I = *this->Internals;
  if (!I.Table || tableSize < 2 || chordSize < 1 || deviationSize < 1)
  {
    return -1.0;
  }
  // The candidate's entries come from the store given (the entries its centre size shares
  // with other candidates) when they lie on its grid, else from a store of its own grid.
  vtkPreIntegrationCandidateEntries::Lookup lookup;
  const vtkInternals::Subset* subset = nullptr;
  if (shared &&
    shared->MakeLookup(tableSize, chordSize, chordRange, deviationSize, deviationRange, lookup))
  {
    for (const vtkInternals::Subset& s : I.Subsets)
    {
      subset = s.Store == shared ? &s : subset;
    }
  }
  else
  {
    if (!I.Entries.Allocate(
          I.Table, prefilter, tableSize, chordSize, chordRange, deviationSize, deviationRange) ||
      !I.Entries.MakeLookup(
        tableSize, chordSize, chordRange, deviationSize, deviationRange, lookup))
    {
      return -1.0;
    }
  }
  return I.MeasurePieces(lookup,
    I.LastPerRay,
    static_cast<size_t>(std::max<vtkIdType>(begin, 0)),
    end < 0 ? I.Rays.size() : static_cast<size_t>(end),
    subset);
}

//------------------------------------------------------------------------------
vtkIdType vtkPreIntegrationTableSizer::GetScreeningRays() const
{
  const vtkIdType rays = static_cast<vtkIdType>(this->Internals->Rays.size());
  const vtkIdType screened = static_cast<vtkIdType>(std::ceil(this->ScreeningFraction * rays));
  return std::min(rays, std::max<vtkIdType>(screened, 256));
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizer::GetLastMeasurePerRay(vtkDoubleArray* errors)
{
  const std::vector<double>& perRay = this->Internals->LastPerRay;
  errors->SetNumberOfComponents(1);
  errors->SetNumberOfTuples(static_cast<vtkIdType>(perRay.size()));
  std::copy(perRay.begin(), perRay.end(), errors->GetPointer(0));
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizer::Choose(vtkImageData* volume,
  vtkDataArray* scalars,
  vtkSecondOrderPreIntegrationTable* table,
  int order,
  double sampleDistance)
{
  const double start = vtkTimerLog::GetUniversalTime();
  if (!this->Prepare(volume, scalars, table, order, sampleDistance))
  {
    return false;
  }
  vtkInternals& I = *this->Internals;
  const double* range = table->GetScalarRange();
  const double width = range[1] - range[0];
  // A margin for the image's many more rays; never beyond the scalar range, never zero.
  const double chordRange =
    std::min(std::max(1.25 * this->MeasuredChordRange, 1e-3 * width), width);
  const double deviationRange =
    std::min(std::max(1.25 * this->MeasuredDeviationRange, 1e-3 * width), width);

  // Candidates: 2^k + 1 centre entries, chord and deviation spacings 1, 2, 4 or 8 times the
  // centre spacing (odd sizes: entry 0 of the axis in the middle), their extents whole
  // spacings that cover the measured ones, so that the entries of a centre size's candidates
  // lie on one grid (the finest spacing's) and are integrated once for all of them. An axis cut
  // to MaximumAxisSize spans the measured extent instead.
  auto axis = [&](double extent, double spacing, double& covered)
  {
    const double half = std::max(std::ceil(extent / spacing - 1e-9), 1.0);
    if (2.0 * half + 1.0 > this->MaximumAxisSize)
    {
      covered = extent;
      return std::max(this->MaximumAxisSize - (this->MaximumAxisSize % 2 == 0 ? 1 : 0), 3);
    }
    covered = half * spacing;
    return static_cast<int>(2.0 * half + 1.0);
  };
  auto makeCandidate = [&](int centreLevel, int chordFactor, int deviationFactor, bool prefilter)
  {
    Candidate c;
    c.Prefilter = prefilter;
    // 2^k + 1 entries, or as many as an axis can hold (a texture limit is often a power of 2).
    c.Sizes[0] = std::min((1 << centreLevel) + 1, this->MaximumAxisSize);
    const double spacing = width / (c.Sizes[0] - 1);
    c.Sizes[1] = axis(chordRange, chordFactor * spacing, c.Ranges[0]);
    c.Sizes[2] = 1;
    c.Ranges[1] = deviationRange;
    if (order == 2)
    {
      c.Sizes[2] = axis(deviationRange, deviationFactor * spacing, c.Ranges[1]);
    }
    c.Memory = static_cast<double>(c.Sizes[0]) * c.Sizes[1] * c.Sizes[2] * this->BytesPerEntry;
    c.Error = -1.0;
    c.Dropped = false;
    return c;
  };
  auto fits = [&](const Candidate& c) { return c.Memory <= this->MaximumMemory; };
  // Each candidate is measured on the screening rays first, and on the others unless they
  // drop it; the comparisons run over the rays [0, active), and while screening over every
  // candidate measured (dropped or not), else over those measured on all the rays.
  const size_t all = I.Rays.size();
  const size_t screen = static_cast<size_t>(this->GetScreeningRays());
  size_t active = all;
  bool screening = false;
  auto evaluate = [&](Candidate c, const vtkPreIntegrationCandidateEntries* shared)
  {
    for (int i = 0; i < static_cast<int>(I.Candidates.size()); ++i)
    {
      const Candidate& o = I.Candidates[i];
      // Of two spacings that give the same sizes, the finer one's (smaller) extents: the
      // same memory, and entries closer to the values the rays read.
      if (std::equal(c.Sizes, c.Sizes + 3, o.Sizes) && c.Prefilter == o.Prefilter)
      {
        return i;
      }
    }
    c.Error = this->MeasureCandidate(c.Sizes[0],
      c.Sizes[1],
      c.Sizes[2],
      c.Ranges[0],
      c.Ranges[1],
      c.Prefilter,
      shared,
      0,
      static_cast<vtkIdType>(screen));
    c.PerRay = I.LastPerRay;
    I.Candidates.push_back(c);
    return static_cast<int>(I.Candidates.size()) - 1;
  };
  // The last Choose()'s shared entries (its last centre size's): a store of the same grid
  // takes the new transfer functions and keeps the entries that read no changed sample; the
  // others are freed.
  std::vector<std::unique_ptr<vtkPreIntegrationCandidateEntries>> last = std::move(I.Stores);
  I.Stores.clear();
  // The store of a centre size's candidates (of one prefilter): the finest of their spacings
  // on each axis, over the widest of their extents; none when it would hold more than twice
  // the entries a table may have (the finest spacings of two axes belonging to candidates too
  // large on the other), as the candidates then share little.
  auto share = [&](const std::vector<Candidate>& level, bool prefilter)
  {
    std::unique_ptr<vtkPreIntegrationCandidateEntries> store;
    const double spacing = width / (level.front().Sizes[0] - 1);
    double step[2] = { 0.0, 0.0 }, extent[2] = { 0.0, 0.0 };
    for (const Candidate& c : level)
    {
      for (int a = 0; a < 2; ++a)
      {
        const double s = c.Sizes[a + 1] > 1 ? 2.0 * c.Ranges[a] / (c.Sizes[a + 1] - 1) : 0.0;
        step[a] = step[a] > 0.0 ? std::min(step[a], s) : s;
        extent[a] = std::max(extent[a], c.Ranges[a]);
      }
    }
    int sizes[2];
    for (int a = 0; a < 2; ++a)
    {
      // A whole multiple of the centre spacing: the candidates' spacings are.
      step[a] = std::max(std::round(step[a] / spacing), 1.0) * spacing;
      sizes[a] =
        order == 1 && a == 1 ? 1 : 2 * static_cast<int>(std::ceil(extent[a] / step[a] - 1e-9)) + 1;
    }
    const double entries = static_cast<double>(level.front().Sizes[0]) * sizes[0] * sizes[1];
    if (entries * this->BytesPerEntry > 2.0 * this->MaximumMemory)
    {
      return store;
    }
    const double ranges[2] = { 0.5 * (sizes[0] - 1) * step[0], 0.5 * (sizes[1] - 1) * step[1] };
    for (auto& before : last)
    {
      if (before &&
        before->Update(
          table, prefilter, level.front().Sizes[0], sizes[0], ranges[0], sizes[1], ranges[1]))
      {
        return std::move(before);
      }
    }
    store.reset(new vtkPreIntegrationCandidateEntries);
    if (!store->Allocate(
          table, prefilter, level.front().Sizes[0], sizes[0], ranges[0], sizes[1], ranges[1]))
    {
      store.reset();
    }
    return store;
  };
  // Mean squared error of candidate i over the rays begin, begin + stride, ...
  auto subsetError = [&](int i, int begin, int stride)
  {
    const std::vector<double>& e = I.Candidates[i].PerRay;
    double sum = 0.0;
    int count = 0;
    for (size_t r = begin; r < active; r += stride, ++count)
    {
      sum += e[r];
    }
    return count > 0 ? sum / count : 0.0;
  };
  auto bestOn = [&](int begin, int stride)
  {
    int least = -1;
    double leastError = 0.0;
    for (int i = 0; i < static_cast<int>(I.Candidates.size()); ++i)
    {
      if (I.Candidates[i].Error < 0.0 || (I.Candidates[i].Dropped && !screening))
      {
        continue;
      }
      const double error = subsetError(i, begin, stride);
      if (least < 0 || error < leastError)
      {
        least = i;
        leastError = error;
      }
    }
    return least;
  };
  auto best = [&]() { return bestOn(0, 1); };
  // Within `tolerance` of the best on the rays begin, begin + stride, ..., with confidence:
  // the rays are the same for every candidate, so the difference of two candidates' mean
  // squared errors has the standard error of the per-ray differences; the mean squared error
  // plus `margin` of those must be within (1 + tolerance)^2 of the best's.
  auto within = [&](int i, int begin, int stride, double tolerance, double margin)
  {
    const int b = bestOn(begin, stride);
    if (i == b)
    {
      return true;
    }
    const std::vector<double>& ci = I.Candidates[i].PerRay;
    const std::vector<double>& cb = I.Candidates[b].PerRay;
    double mean = 0.0, square = 0.0;
    int n = 0;
    for (size_t r = begin; r < active; r += stride, ++n)
    {
      const double d = ci[r] - cb[r];
      mean += d;
      square += d * d;
    }
    n = std::max(n, 1);
    mean /= n;
    const double deviation = std::sqrt(std::max(square / n - mean * mean, 0.0) / n);
    const double bestSquare = subsetError(b, begin, stride);
    const double allowed = (1.0 + tolerance) * (1.0 + tolerance);
    return bestSquare + mean + margin * deviation <= allowed * bestSquare;
  };
  auto goodOn = [&](int i, int begin, int stride)
  { return within(i, begin, stride, this->Tolerance, 2.0); };
  // Whether candidate i is, with confidence, within half the Tolerance of the exact segment
  // model (or better): finer tables converge to that model, so the search can stop there.
  // Confidence matters: a finer table can still beat the model by far more than a level
  // within half the Tolerance of it as measured suggests.
  auto nearExact = [&](int i)
  {
    const std::vector<double>& exact = I.ExactPerRay;
    if (i < 0 || I.Candidates[i].Dropped || exact.empty() ||
      exact.size() != I.Candidates[i].PerRay.size())
    {
      return false;
    }
    const std::vector<double>& ci = I.Candidates[i].PerRay;
    double mean = 0.0, square = 0.0, exactSquare = 0.0;
    const size_t n = std::max<size_t>(ci.size(), 1);
    for (size_t r = 0; r < ci.size(); ++r)
    {
      const double d = ci[r] - exact[r];
      mean += d;
      square += d * d;
      exactSquare += exact[r];
    }
    mean /= n;
    exactSquare /= n;
    const double deviation = std::sqrt(std::max(square / n - mean * mean, 0.0) / n);
    const double allowed = (1.0 + 0.5 * this->Tolerance) * (1.0 + 0.5 * this->Tolerance);
    return exactSquare + mean + 2.0 * deviation <= allowed * exactSquare;
  };

  // Every candidate that fits, coarse to fine: coarse tables can measure better than finer
  // ones (their interpolation smooths over the segment model's own error) on one axis and not
  // another, so no search that skips some of them finds the best reliably. Finer centre axes
  // converge to the segment model itself: once two sizes in a row improve on the coarser
  // sizes' best by less than half the Tolerance, the finer ones (the costliest) are not
  // measured. One such size is not enough: a size too coarse for a narrow feature can stall
  // before the next resolves it.
  const int factors[4] = { 1, 2, 4, 8 };
  const bool kept = table->GetPrefilter();
  this->NumberOfLevels = 0;
  double coarserBest = -1.0;
  int stalled = 0; // centre sizes in a row that did not improve the best
  for (int level = 5; level <= 16; ++level)
  {
    const size_t first = I.Candidates.size();
    if (I.AbortRequested)
    {
      return this->Stop();
    }
    if (!fits(makeCandidate(level, 8, order == 2 ? 8 : 1, kept)))
    {
      break; // every coarser spacing of this centre size is larger still
    }
    const bool last = (1 << level) + 1 >= this->MaximumAxisSize;
    std::vector<Candidate> fitting[2]; // without and with the prefilter
    for (int fb : factors)
    {
      for (int fd : factors)
      {
        if (order == 1 && fd != 1)
        {
          continue;
        }
        for (int p = 0; p < (this->MeasurePrefilter ? 2 : 1); ++p)
        {
          const bool prefilter = this->MeasurePrefilter ? p == 1 : kept;
          const Candidate c = makeCandidate(level, fb, order == 2 ? fd : 1, prefilter);
          if (fits(c))
          {
            fitting[prefilter ? 1 : 0].push_back(c);
          }
        }
      }
    }
    // The entries this centre size's candidates share: without and with the prefilter.
    std::unique_ptr<vtkPreIntegrationCandidateEntries> shared[2];
    for (int p = 0; p < 2; ++p)
    {
      shared[p] = fitting[p].empty() ? nullptr : share(fitting[p], p == 1);
      I.Subsets[p].Store = nullptr;
      if (shared[p])
      {
        // How far the candidates' entries reach from a piece, and the axis values all of
        // them cover (a single entry's axis holds 0 alone).
        double reach[3] = { width / (fitting[p].front().Sizes[0] - 1), 0.0, 0.0 };
        double low[3] = { range[0], 0.0, 0.0 }, high[3] = { range[1], 0.0, 0.0 };
        bool first = true;
        for (const Candidate& c : fitting[p])
        {
          for (int a = 1; a < 3; ++a)
          {
            const double extent = c.Sizes[a] > 1 ? c.Ranges[a - 1] : 0.0;
            reach[a] = std::max(reach[a], c.Sizes[a] > 1 ? 2.0 * extent / (c.Sizes[a] - 1) : 0.0);
            high[a] = first ? extent : std::min(high[a], extent);
            low[a] = -high[a];
          }
          first = false;
        }
        I.MakeSubset(shared[p].get(), reach, low, high, I.Subsets[p]);
      }
    }
    // Finest first, as the loops made them: the coarser candidates then find most of their
    // entries integrated.
    for (size_t i = 0; i < std::max(fitting[0].size(), fitting[1].size()); ++i)
    {
      for (int p = 0; p < 2; ++p)
      {
        if (i < fitting[p].size())
        {
          evaluate(fitting[p][i], shared[p].get());
        }
      }
    }
    // The screening: this centre size's candidates that the screening rays cannot tell, with
    // confidence, are out of twice the Tolerance of the best so far are measured on the
    // others too; the rest are dropped.
    if (screen < all)
    {
      active = screen;
      screening = true;
      for (size_t i = first; i < I.Candidates.size(); ++i)
      {
        Candidate& c = I.Candidates[i];
        c.Dropped =
          c.Error >= 0.0 && !within(static_cast<int>(i), 0, 1, 2.0 * this->Tolerance, -2.0);
      }
      active = all;
      screening = false;
      for (size_t i = first; i < I.Candidates.size(); ++i)
      {
        Candidate& c = I.Candidates[i];
        if (c.Error < 0.0 || c.Dropped)
        {
          continue;
        }
        const double rest = this->MeasureCandidate(c.Sizes[0],
          c.Sizes[1],
          c.Sizes[2],
          c.Ranges[0],
          c.Ranges[1],
          c.Prefilter,
          shared[c.Prefilter ? 1 : 0].get(),
          static_cast<vtkIdType>(screen),
          static_cast<vtkIdType>(all));
        if (I.AbortRequested)
        {
          return this->Stop();
        }
        std::copy(I.LastPerRay.begin() + screen, I.LastPerRay.end(), c.PerRay.begin() + screen);
        double sum = 0.0;
        for (double e : c.PerRay)
        {
          sum += e;
        }
        c.Error = rest < 0.0 ? -1.0 : std::sqrt(sum / std::max<size_t>(all, 1));
      }
    }
    for (vtkInternals::Subset& subset : I.Subsets)
    {
      subset.Store = nullptr; // its store is kept, or freed, below
    }
    // Only the last centre size's stores are kept (the largest, where most entries are
    // integrated): a Choose() holds no more stores at once than one centre size's.
    for (int p = 0; p < 2 && this->KeepEntries; ++p)
    {
      if (p == 0)
      {
        I.Stores.clear();
      }
      if (shared[p])
      {
        I.Stores.push_back(std::move(shared[p]));
      }
    }
    ++this->NumberOfLevels;
    // The levels ahead are not known: each measured one goes half the rest of the way.
    this->ReportProgress(1.0 - 0.55 * std::pow(0.5, this->NumberOfLevels));
    if (last)
    {
      break; // the centre axis is as large as it can be
    }
    double levelBest = -1.0;
    int levelBestIndex = -1;
    for (size_t i = first; i < I.Candidates.size(); ++i)
    {
      const double e = I.Candidates[i].Dropped ? -1.0 : I.Candidates[i].Error;
      if (e >= 0.0 && (levelBest < 0.0 || e < levelBest))
      {
        levelBest = e;
        levelBestIndex = static_cast<int>(i);
      }
    }
    if (this->StopAtConvergence && nearExact(levelBestIndex))
    {
      break;
    }
    if (coarserBest >= 0.0 && levelBest >= 0.0 &&
      levelBest >= (1.0 - 0.5 * this->Tolerance) * coarserBest)
    {
      if (++stalled >= 2 && this->StopAtConvergence)
      {
        break;
      }
    }
    else
    {
      stalled = 0;
    }
    if (levelBest >= 0.0 && (coarserBest < 0.0 || levelBest < coarserBest))
    {
      coarserBest = levelBest;
    }
  }

  if (I.AbortRequested)
  {
    return this->Stop();
  }

  // Good on all the rays and on `halves` of their halves (so that a table good only by the
  // luck of a few rays, whose errors dominate the mean, is less likely chosen: the per-ray
  // errors are heavy-tailed, rays grazing a sharp feature carry most of the error).
  auto goodAt = [&](int i, int halves)
  {
    return I.Candidates[i].Error >= 0.0 && !I.Candidates[i].Dropped && goodOn(i, 0, 1) &&
      static_cast<int>(goodOn(i, 0, 2)) + static_cast<int>(goodOn(i, 1, 2)) >= halves;
  };
  // The least memory among the candidates good at `halves`; of equal memory (with and without
  // the prefilter), the smaller error.
  auto leastMemory = [&](int halves)
  {
    int chosen = -1;
    for (int i = 0; i < static_cast<int>(I.Candidates.size()); ++i)
    {
      const Candidate& c = I.Candidates[i];
      if (!goodAt(i, halves))
      {
        continue;
      }
      const Candidate* least = chosen < 0 ? nullptr : &I.Candidates[chosen];
      if (!least || c.Memory < least->Memory ||
        (c.Memory == least->Memory && c.Error < least->Error))
      {
        chosen = i;
      }
    }
    return chosen;
  };
  this->ChosenCandidate = leastMemory(2);
  if (this->ChosenCandidate < 0)
  {
    // The halves' bests differ by more than their rays can resolve (heavy tails), so that no
    // candidate, often not even the best, is good on both: good on all the rays and one half.
    this->ChosenCandidate = leastMemory(1);
  }
  // The sizes in use stay while they are good on all the rays and on one half at least (the
  // fallback's standard) and cost at most twice the least memory: near-equal candidates
  // otherwise trade places from edit to edit (the rays cannot tell them apart, and the halves
  // even less), and each trade rebuilds the table and outdates a drag's provisional one.
  for (int i = 0; i < static_cast<int>(I.Candidates.size()) && this->ChosenCandidate >= 0; ++i)
  {
    const Candidate& c = I.Candidates[i];
    if (i != this->ChosenCandidate && c.Sizes[0] == table->GetTableSize() &&
      c.Sizes[1] == table->GetChordSize() && c.Sizes[2] == table->GetDeviationSize() &&
      c.Ranges[0] == table->GetChordRange() && c.Ranges[1] == table->GetDeviationRange() &&
      c.Prefilter == table->GetPrefilter() && goodAt(i, 1) &&
      c.Memory <= 2.0 * I.Candidates[this->ChosenCandidate].Memory)
    {
      this->ChosenCandidate = i;
      break;
    }
  }
  if (this->ChosenCandidate < 0)
  {
    this->ChosenCandidate = best();
  }
  if (this->ChosenCandidate < 0)
  {
    vtkErrorMacro("No candidate table fits in " << this->MaximumMemory << " bytes.");
    return false;
  }
  const Candidate& chosen = I.Candidates[this->ChosenCandidate];
  table->SetTableSize(chosen.Sizes[0]);
  table->SetChordSize(chosen.Sizes[1]);
  table->SetDeviationSize(chosen.Sizes[2]);
  table->SetChordRange(chosen.Ranges[0]);
  table->SetDeviationRange(chosen.Ranges[1]);
  if (this->MeasurePrefilter)
  {
    table->SetPrefilter(chosen.Prefilter);
  }
  this->LastChooseTime = vtkTimerLog::GetUniversalTime() - start;
  this->ReportProgress(1.0);
  return true;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizer::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfRays: " << this->NumberOfRays << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "MaximumMemory: " << this->MaximumMemory << "\n";
  os << indent << "BytesPerEntry: " << this->BytesPerEntry << "\n";
  os << indent << "MaximumAxisSize: " << this->MaximumAxisSize << "\n";
  os << indent << "OpacityThreshold: " << this->OpacityThreshold << "\n";
  os << indent << "ReferenceTolerance: " << this->ReferenceTolerance << "\n";
  os << indent << "StopAtConvergence: " << this->StopAtConvergence << "\n";
  os << indent << "KeepEntries: " << this->KeepEntries << "\n";
  os << indent << "ScreeningFraction: " << this->ScreeningFraction << "\n";
  os << indent << "MeasurePrefilter: " << this->MeasurePrefilter << "\n";
  os << indent << "ChosenCandidate: " << this->ChosenCandidate << "\n";
  os << indent << "ExactError: " << this->ExactError << "\n";
}
