// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkFirstOrderPreIntegrationTable.h"

#include "vtkFloatArray.h"
#include "vtkObjectFactory.h"
#include "vtkSMPTools.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

vtkStandardNewMacro(vtkFirstOrderPreIntegrationTable);

//------------------------------------------------------------------------------
vtkFirstOrderPreIntegrationTable::vtkFirstOrderPreIntegrationTable() = default;

//------------------------------------------------------------------------------
vtkFirstOrderPreIntegrationTable::~vtkFirstOrderPreIntegrationTable() = default;

//------------------------------------------------------------------------------
void vtkFirstOrderPreIntegrationTable::BuildTable()
{
  const int n = this->TableSize;
  const int k = this->GetEffectiveSubSamples();
  const double s0 = this->ScalarRange[0];
  const double spacing = (this->ScalarRange[1] - this->ScalarRange[0]) / (n - 1);
  const double d = this->SegmentLength;

  // Transfer function at the nodes (for constant segments) and at the midpoints of the
  // k pieces of every table spacing: q -> s0 + (q + 1/2) spacing / k.
  std::vector<double> atNode(4 * static_cast<size_t>(n));
  std::vector<double> atPiece(4 * static_cast<size_t>(n - 1) * k);
  this->Sampler->Sample(s0, this->ScalarRange[1], n, atNode.data());
  for (int q = 0; q < (n - 1) * k; ++q)
  {
    this->Sampler->Evaluate(s0 + (q + 0.5) * spacing / k, atPiece.data() + 4 * q);
  }

  float* table = this->Table->GetPointer(0);
  auto store = [table, n](vtkIdType i, vtkIdType j, const double rgb[3], double transmittance)
  {
    float* out = table + 4 * (j * static_cast<vtkIdType>(n) + i);
    out[0] = static_cast<float>(rgb[0]);
    out[1] = static_cast<float>(rgb[1]);
    out[2] = static_cast<float>(rgb[2]);
    out[3] = static_cast<float>(1.0 - transmittance);
  };
  // Entries of one scalar difference m = |j - i| share the piece length d / (m k), so each
  // piece's opacity is one exponential per difference, not one per entry that crosses it.
  const int pieceCount = (n - 1) * k;
  this->ForInParts(n,
    [&](vtkIdType mBegin, vtkIdType mEnd)
    {
      std::vector<double> alphas(static_cast<size_t>(pieceCount));
      for (vtkIdType m = mBegin; m < mEnd; ++m)
      {
        if (m == 0)
        {
          for (int i = 0; i < n; ++i)
          {
            const double* f = atNode.data() + 4 * i;
            const double alpha = -std::expm1(-f[3] * d);
            const double rgb[3] = { f[0] * alpha, f[1] * alpha, f[2] * alpha };
            store(i, i, rgb, 1.0 - alpha);
          }
          continue;
        }
        const int pieces = static_cast<int>(m) * k;
        const double h = d / pieces;
        for (int q = 0; q < pieceCount; ++q)
        {
          alphas[q] = -std::expm1(-atPiece[4 * q + 3] * h);
        }
        for (int i = 0; i + m < n; ++i)
        {
          // Walk the pieces from the front scalar to the back scalar: upwards from i to
          // j = i + m, and downwards from j to i.
          for (int direction = 0; direction < 2; ++direction)
          {
            const int front = direction == 0 ? i : static_cast<int>(i + m);
            const int first = direction == 0 ? front * k : front * k - 1;
            const int step = direction == 0 ? 1 : -1;
            double rgb[3] = { 0, 0, 0 };
            double transmittance = 1.0;
            for (int p = 0; p < pieces; ++p)
            {
              const int q = first + step * p;
              const double* f = atPiece.data() + 4 * q;
              const double alpha = alphas[q];
              const double w = transmittance * alpha;
              rgb[0] += w * f[0];
              rgb[1] += w * f[1];
              rgb[2] += w * f[2];
              transmittance *= 1.0 - alpha;
            }
            store(front, direction == 0 ? i + m : i, rgb, transmittance);
          }
        }
      }
    });
}

//------------------------------------------------------------------------------
void vtkFirstOrderPreIntegrationTable::AppendBuildKey(std::vector<double>& key) const
{
  this->Superclass::AppendBuildKey(key);
  key.push_back(static_cast<double>(this->GetEffectiveSubSamples()));
}

//------------------------------------------------------------------------------
int vtkFirstOrderPreIntegrationTable::GetEffectiveSubSamples() const
{
  return this->SubSamples > 0 ? this->SubSamples
                              : std::max(1, std::min(4, 1024 / std::max(this->TableSize, 1)));
}

//------------------------------------------------------------------------------
void vtkFirstOrderPreIntegrationTable::GetEntry(int front, int back, double rgba[4])
{
  const vtkIdType index = static_cast<vtkIdType>(back) * this->TableSize + front;
  for (int c = 0; c < 4; ++c)
  {
    rgba[c] = this->Table->GetTypedComponent(index, c);
  }
}

//------------------------------------------------------------------------------
void vtkFirstOrderPreIntegrationTable::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SubSamples: " << this->SubSamples << "\n";
}
