// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkSecondOrderPreIntegrationTable.h"

#include "vtkFloatArray.h"
#include "vtkObjectFactory.h"
#include "vtkSMPTools.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkSecondOrderPreIntegrationTable);

//------------------------------------------------------------------------------
vtkSecondOrderPreIntegrationTable::vtkSecondOrderPreIntegrationTable()
  : IterationTable(vtkFloatArray::New())
  , IterationEmptyRuns(vtkFloatArray::New())
{
  this->IterationTable->SetNumberOfComponents(4);
  this->SegmentLength = 2.0;
}

//------------------------------------------------------------------------------
vtkSecondOrderPreIntegrationTable::~vtkSecondOrderPreIntegrationTable()
{
  this->IterationTable->Delete();
  this->IterationEmptyRuns->Delete();
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::BuildIterationTable()
{
  const int n = this->TableSize;
  const double width = this->ScalarRange[1] - this->ScalarRange[0];
  const double tableSpacing = width / (n - 1);
  const double feature = this->Sampler->GetSmallestFeature();
  const double wanted = std::ceil(16.0 * tableSpacing / feature);
  this->IterationSamplesPerSpacing =
    static_cast<int>(std::max(8.0, std::min(wanted, 65536.0 / (n - 1))));
  int fine = this->IterationSamplesPerSpacing * (n - 1) + 1;
  this->EntryPositions.resize(n);
  if (this->AdaptiveAxes)
  {
    // Entries are not equispaced: a grid fine enough for 16 samples per narrowest feature
    // over the whole range, with the entries at fractional positions in it.
    fine = static_cast<int>(
      std::max(static_cast<double>(fine), std::min(16.0 * width / feature, 1048576.0) + 1.0));
    for (int i = 0; i < n; ++i)
    {
      this->EntryPositions[i] =
        (this->GetEntryScalar(i) - this->ScalarRange[0]) / width * (fine - 1.0);
    }
  }
  else
  {
    for (int i = 0; i < n; ++i)
    {
      this->EntryPositions[i] = static_cast<double>(this->IterationSamplesPerSpacing) * i;
    }
  }
  const double s0 = this->ScalarRange[0];
  const double spacing = width / (fine - 1);
  // The last sample exactly at ScalarRange[1]: s0 + (fine - 1) spacing can miss it by a
  // rounding error, which matters for a transfer-function step at the range end.
  const double s1 = this->ScalarRange[1];
  auto scalar = [&](int q) { return q == fine - 1 ? s1 : s0 + q * spacing; };
  const double step = this->SegmentLength / this->Iterations;
  this->IterationTable->SetNumberOfTuples(fine);
  float* values = this->IterationTable->GetPointer(0);
  for (int q = 0; q < fine; ++q)
  {
    double rgbTau[4];
    this->Sampler->Evaluate(scalar(q), rgbTau);
    const double alpha = -std::expm1(-rgbTau[3] * step);
    values[4 * q + 0] = static_cast<float>(rgbTau[0] * alpha);
    values[4 * q + 1] = static_cast<float>(rgbTau[1] * alpha);
    values[4 * q + 2] = static_cast<float>(rgbTau[2] * alpha);
    values[4 * q + 3] = static_cast<float>(alpha);
  }
  this->IterationEmptyRuns->SetNumberOfTuples(fine - 1);
  int run = -1;
  bool inRun = false;
  for (int q = 0; q < fine - 1; ++q)
  {
    const bool empty = this->Sampler->GetMaximumOpacity(scalar(q), scalar(q + 1)) <= 0.0;
    run += empty && !inRun ? 1 : 0;
    inRun = empty;
    this->IterationEmptyRuns->SetValue(q, empty ? static_cast<float>(run) : -1.0f);
  }
}

//------------------------------------------------------------------------------
namespace
{
// Integrates the slabs (front, middle, back) and (back, middle, front) of one table. The two
// follow the same scalar path in opposite directions: they share the iteration-table lookups
// (the costly part) and differ only in the order of compositing.
class SlabIntegrator
{
public:
  int N;
  const double* Positions; // of the entries, in iteration-table samples
  const double* Scalars;   // of the entries
  int Fine;
  int Iterations;
  double Length;
  double S0;
  double S1;
  const float* Steps;
  const float* Runs;
  const vtkVolumeTransferFunctionSampler* Sampler;
  float* Table;

  float* Entry(int front, int middle, int back) const
  {
    return this->Table + 4 * (front + static_cast<vtkIdType>(this->N) * (middle + this->N * back));
  }

  static constexpr int Lanes = 4;

  // Scratch memory of one task.
  struct Scratch
  {
    std::vector<float> X, W, Steps;
    std::vector<int> Q;
  };

  // Integrates, both ways, the slabs of up to Lanes fronts sharing middle j and back k. The
  // compositing loops carry one multiplication chain per lane and direction; interleaving them
  // keeps the processor busy instead of waiting on one chain.
  void IntegrateBatch(const int* fronts, int count, int j, int k, Scratch& scratch) const
  {
    const int n = this->Iterations;
    const float h = 1.0f / n;
    const float top = static_cast<float>(this->Fine - 1);
    for (int lane = 0; lane < count; ++lane)
    {
      // Eq. 2 in units of iteration-table samples; P(t) by Horner's rule in float, as the
      // GPU builder does. The loops are split so that the first two vectorise.
      const float xf = static_cast<float>(this->Positions[fronts[lane]]);
      const float xm = static_cast<float>(this->Positions[j]);
      const float xb = static_cast<float>(this->Positions[k]);
      const float a = 2.0f * xf - 4.0f * xm + 2.0f * xb;
      const float b = -3.0f * xf + 4.0f * xm - xb;
      float* x = scratch.X.data();
      float* w = scratch.W.data();
      int* q = scratch.Q.data();
      for (int it = 0; it < n; ++it)
      {
        const float t = (it + 0.5f) * h;
        x[it] = std::min(std::max(xf + t * (b + a * t), 0.0f), top);
      }
      for (int it = 0; it < n; ++it)
      {
        const int qi = static_cast<int>(x[it]);
        q[it] = qi < this->Fine - 2 ? qi : this->Fine - 2;
        w[it] = x[it] - static_cast<float>(q[it]);
      }
      float* step = scratch.Steps.data() + 4 * n * lane;
      for (int it = 0; it < n; ++it)
      {
        const float* v = this->Steps + 4 * q[it];
        for (int c = 0; c < 4; ++c)
        {
          step[4 * it + c] = v[c] + w[it] * (v[c + 4] - v[c]);
        }
      }
    }
    // Front to back: RGBA += T (c a, a), T *= 1 - a. Alpha is accumulated like the colour,
    // not taken as 1 - T: in float 1 - a is a multiple of 2^-24, so T would drop steps with
    // a below 3e-8 and distort those below ~1e-5 (thin media, short slabs) while their colour
    // still counted.
    float f[Lanes][4], g[Lanes][4], tf[Lanes], tg[Lanes];
    for (int lane = 0; lane < Lanes; ++lane)
    {
      std::fill(f[lane], f[lane] + 4, 0.0f);
      std::fill(g[lane], g[lane] + 4, 0.0f);
      tf[lane] = tg[lane] = 1.0f;
    }
    const float* steps = scratch.Steps.data();
    for (int it = 0; it < n; ++it)
    {
      for (int lane = 0; lane < count; ++lane)
      {
        const float* u = steps + 4 * (n * lane + it);
        const float* v = steps + 4 * (n * lane + n - 1 - it);
        for (int c = 0; c < 4; ++c)
        {
          f[lane][c] += tf[lane] * u[c];
          g[lane][c] += tg[lane] * v[c];
        }
        tf[lane] *= 1.0f - u[3];
        tg[lane] *= 1.0f - v[3];
      }
    }
    for (int lane = 0; lane < count; ++lane)
    {
      float* forward = this->Entry(fronts[lane], j, k);
      float* backward = this->Entry(k, j, fronts[lane]);
      for (int c = 0; c < 3; ++c)
      {
        forward[c] = f[lane][c];
        backward[c] = g[lane][c];
      }
      forward[3] = std::min(f[lane][3], 1.0f); // sum of T a: 1 at most, up to rounding
      backward[3] = std::min(g[lane][3], 1.0f);
    }
  }

  void operator()(vtkIdType kBegin, vtkIdType kEnd) const
  {
    Scratch scratch;
    scratch.X.resize(this->Iterations);
    scratch.W.resize(this->Iterations);
    scratch.Q.resize(this->Iterations);
    scratch.Steps.resize(4 * this->Iterations * Lanes);
    for (vtkIdType kk = kBegin; kk < kEnd; ++kk)
    {
      const int k = static_cast<int>(kk);
      for (int j = 0; j < this->N; ++j)
      {
        int batch[Lanes];
        int pending = 0;
        for (int i = 0; i <= k; ++i)
        {
          float* forward = this->Entry(i, j, k);
          float* backward = this->Entry(k, j, i);
          // The range of P over [0, 1]: its ends, and its extremum when inside.
          const double xf = this->Positions[i], xm = this->Positions[j];
          const double xb = this->Positions[k];
          const double a = 2.0 * xf - 4.0 * xm + 2.0 * xb;
          const double b = -3.0 * xf + 4.0 * xm - xb;
          double lo = std::min(xf, xb), hi = std::max(xf, xb);
          const double vertex = a != 0.0 ? -b / (2.0 * a) : -1.0;
          if (vertex > 0.0 && vertex < 1.0)
          {
            const double extremum = xf + vertex * (b + a * vertex);
            lo = std::min(lo, extremum);
            hi = std::max(hi, extremum);
          }
          lo = std::max(lo, 0.0);
          hi = std::min(hi, this->Fine - 1.0);
          if (hi == lo)
          {
            // Constant scalar (the table diagonal, or clamped): the exact exponential.
            double rgbTau[4];
            // The exact scalar: a range end when clamped, else the entry's own.
            this->Sampler->Evaluate(lo <= 0.0 ? this->S0
                : lo >= this->Fine - 1.0      ? this->S1
                                              : this->Scalars[i],
              rgbTau);
            const double alpha = -std::expm1(-rgbTau[3] * this->Length);
            for (float* out : { forward, backward })
            {
              out[0] = static_cast<float>(rgbTau[0] * alpha);
              out[1] = static_cast<float>(rgbTau[1] * alpha);
              out[2] = static_cast<float>(rgbTau[2] * alpha);
              out[3] = static_cast<float>(alpha);
            }
            continue;
          }
          const int qlo = std::min(static_cast<int>(lo), this->Fine - 2);
          const int qhi = std::min(static_cast<int>(hi), this->Fine - 2);
          if (this->Runs[qlo] >= 0.0f && this->Runs[qlo] == this->Runs[qhi])
          {
            std::fill(forward, forward + 4, 0.0f); // inside one zero-opacity run
            std::fill(backward, backward + 4, 0.0f);
            continue;
          }
          batch[pending++] = i;
          if (pending == Lanes)
          {
            this->IntegrateBatch(batch, pending, j, k, scratch);
            pending = 0;
          }
        }
        if (pending > 0)
        {
          this->IntegrateBatch(batch, pending, j, k, scratch);
        }
      }
    }
  }
};
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::BuildTable()
{
  this->BuildIterationTable();
  if (!this->ComputeEntries)
  {
    return; // another builder (the GPU) integrates from the iteration table
  }
  SlabIntegrator integrator;
  integrator.N = this->TableSize;
  integrator.Positions = this->EntryPositions.data();
  integrator.Scalars = this->EntryScalars.data();
  integrator.Fine = this->IterationTable->GetNumberOfTuples();
  integrator.Iterations = this->Iterations;
  integrator.Length = this->SegmentLength;
  integrator.S0 = this->ScalarRange[0];
  integrator.S1 = this->ScalarRange[1];
  integrator.Steps = this->IterationTable->GetPointer(0);
  integrator.Runs = this->IterationEmptyRuns->GetPointer(0);
  integrator.Sampler = this->Sampler;
  integrator.Table = this->Table->GetPointer(0);
  // Slice k integrates k + 1 pairs: many small tasks keep both cores busy.
  vtkSMPTools::For(0, this->TableSize, 1, integrator);
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::GetEntry(int front, int middle, int back, double rgba[4])
{
  const vtkIdType n = this->TableSize;
  const vtkIdType index = front + n * (middle + n * back);
  for (int c = 0; c < 4; ++c)
  {
    rgba[c] = this->Table->GetTypedComponent(index, c);
  }
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Iterations: " << this->Iterations << "\n";
}
