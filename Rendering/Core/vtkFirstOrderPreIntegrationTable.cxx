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
  this->ForInParts(n,
    [&](vtkIdType jBegin, vtkIdType jEnd)
    {
      for (vtkIdType j = jBegin; j < jEnd; ++j) // back scalar: rows
      {
        for (int i = 0; i < n; ++i) // front scalar
        {
          double rgb[3] = { 0, 0, 0 };
          double transmittance = 1.0;
          if (i == j)
          {
            const double* f = atNode.data() + 4 * i;
            const double alpha = -std::expm1(-f[3] * d);
            rgb[0] = f[0] * alpha;
            rgb[1] = f[1] * alpha;
            rgb[2] = f[2] * alpha;
            transmittance = 1.0 - alpha;
          }
          else
          {
            // Walk the pieces from the front scalar to the back scalar.
            const int pieces = static_cast<int>(std::abs(j - i)) * k;
            const double h = d / pieces;
            const int first = j > i ? i * k : i * k - 1;
            const int step = j > i ? 1 : -1;
            for (int p = 0; p < pieces; ++p)
            {
              const double* f = atPiece.data() + 4 * (first + step * p);
              const double alpha = -std::expm1(-f[3] * h);
              const double w = transmittance * alpha;
              rgb[0] += w * f[0];
              rgb[1] += w * f[1];
              rgb[2] += w * f[2];
              transmittance *= 1.0 - alpha;
            }
          }
          float* out = table + 4 * (j * static_cast<vtkIdType>(n) + i);
          out[0] = static_cast<float>(rgb[0]);
          out[1] = static_cast<float>(rgb[1]);
          out[2] = static_cast<float>(rgb[2]);
          out[3] = static_cast<float>(1.0 - transmittance);
        }
      }
    });
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
