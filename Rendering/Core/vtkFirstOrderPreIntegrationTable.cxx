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
  // piece's opacity is one exponential per difference, not one per entry that crosses it. The
  // entries of one difference are windows of L = m k pieces sliding over the pieces: with the
  // pieces cut into blocks of L, a window is the composite of a block's tail and the next
  // block's head, both kept per piece (front-to-back compositing is associative), so a
  // difference costs a few passes over the pieces instead of L per entry.
  const int pieceCount = (n - 1) * k;
  this->ForInParts(n,
    [&](vtkIdType mBegin, vtkIdType mEnd)
    {
      // Premultiplied colour and transmittance of a run of pieces.
      struct Run
      {
        double C[3];
        double T;
      };
      // a in front of b.
      auto over = [](const Run& a, const Run& b) -> Run {
        return { { a.C[0] + a.T * b.C[0], a.C[1] + a.T * b.C[1], a.C[2] + a.T * b.C[2] },
          a.T * b.T };
      };
      const Run clear = { { 0.0, 0.0, 0.0 }, 1.0 };
      std::vector<Run> piece(static_cast<size_t>(pieceCount));
      // Per piece q in block [b, e): head = b..q and tail = q..e front to back (upwards),
      // downHead = q..b and downTail = e..q front to back (downwards).
      std::vector<Run> head(piece.size()), tail(piece.size()), downHead(piece.size()),
        downTail(piece.size());
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
        const int L = static_cast<int>(m) * k;
        const double h = d / L;
        for (int q = 0; q < pieceCount; ++q)
        {
          const double* f = atPiece.data() + 4 * q;
          const double alpha = -std::expm1(-f[3] * h);
          piece[q] = { { f[0] * alpha, f[1] * alpha, f[2] * alpha }, 1.0 - alpha };
        }
        for (int b = 0; b < pieceCount; b += L)
        {
          const int e = std::min(b + L, pieceCount);
          Run up = clear, down = clear;
          for (int q = b; q < e; ++q)
          {
            up = over(up, piece[q]);
            head[q] = up;
            down = over(piece[q], down);
            downHead[q] = down;
          }
          up = clear;
          down = clear;
          for (int q = e - 1; q >= b; --q)
          {
            up = over(piece[q], up);
            tail[q] = up;
            down = over(down, piece[q]);
            downTail[q] = down;
          }
        }
        for (int i = 0; i + m < n; ++i)
        {
          // Pieces a .. a + L - 1, from scalar i up to j = i + m, and back down.
          const int a = i * k;
          const int last = a + L - 1;
          Run upwards, downwards;
          if (a % L == 0)
          {
            upwards = head[last];
            downwards = downHead[last];
          }
          else
          {
            upwards = over(tail[a], head[last]);
            downwards = over(downHead[last], downTail[a]);
          }
          store(i, i + m, upwards.C, upwards.T);
          store(i + m, i, downwards.C, downwards.T);
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
