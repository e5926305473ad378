// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkObjectOrderRayCasterRays.h"

#include "vtkCameraRayModel.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"

#include <algorithm>
#include <cmath>
#include <limits>

//------------------------------------------------------------------------------
void vtkObjectOrderRayCasterRays::Update(vtkCameraRayModel* model,
  vtkMatrix4x4* worldToIndex,
  const int size[2],
  const int cells[3],
  double step)
{
  this->Width = size[0];
  this->Height = size[1];
  std::copy(cells, cells + 3, this->Cells);
  this->Step = step;
  this->SkippedSteps = 0.0;
  this->Piece = false;
  for (int a = 0; a < 3; ++a)
  {
    this->ChordLo[a] = 0.0;
    this->ChordHi[a] = cells[a];
  }
  auto toGrid = [&](const double w[3], double g[3], double h)
  {
    const double in[4] = { w[0], w[1], w[2], h };
    double out[4];
    worldToIndex->MultiplyPoint(in, out);
    std::copy(out, out + 3, g);
  };
  double o00[3], o10[3], o01[3];
  double* d = this->WorldDirection;
  model->GetPixelRay(0, 0, o00, d);
  model->GetPixelRay(1, 0, o10, d);
  model->GetPixelRay(0, 1, o01, d);
  double g10[3], g01[3];
  toGrid(o00, this->O, 1.0);
  toGrid(o10, g10, 1.0);
  toGrid(o01, g01, 1.0);
  toGrid(d, this->D, 0.0);
  vtkMath::Subtract(g10, this->O, this->EX);
  vtkMath::Subtract(g01, this->O, this->EY);
  for (int a = 0; a < 3; ++a)
  {
    this->Still[a] = this->D[a] == 0.0;
    this->InvD[a] = this->Still[a] ? 0.0 : 1.0 / this->D[a];
  }
  double columns[3][3];
  for (int a = 0; a < 3; ++a)
  {
    columns[a][0] = this->EX[a];
    columns[a][1] = this->EY[a];
    columns[a][2] = this->D[a];
  }
  vtkMath::Invert3x3(columns, this->Inverse);
  // Rays start at the camera's plane; a camera far from the volume puts sample indices beyond
  // 2^53, where n + 1 == n. Starting them a whole number of steps later, no nearer than the
  // box's nearest corner, keeps the same samples and small indices.
  double nearest = VTK_DOUBLE_MAX;
  for (int corner = 0; corner < 8; ++corner)
  {
    double c[3];
    for (int a = 0; a < 3; ++a)
    {
      c[a] = ((corner >> a) & 1 ? this->Cells[a] : 0.0) - this->O[a];
    }
    nearest = std::min(nearest, vtkMath::Dot(this->Inverse[2], c));
  }
  if (nearest > step && std::isfinite(nearest))
  {
    this->SkippedSteps = std::floor(nearest / step);
    const double skip = this->SkippedSteps * step;
    for (int a = 0; a < 3; ++a)
    {
      this->O[a] += skip * this->D[a];
    }
  }
  // The pixels whose rays can meet the box of the points: the tiles outside them are left
  // as the output was initialized (transparent), and each tile finds its own pixels' chords.
  const double boxLo[3] = { 0.0, 0.0, 0.0 };
  const double boxHi[3] = { static_cast<double>(this->Cells[0]),
    static_cast<double>(this->Cells[1]),
    static_cast<double>(this->Cells[2]) };
  const int wholeImage[4] = { 0, this->Width - 1, 0, this->Height - 1 };
  if (!this->Rectangle(boxLo, boxHi, wholeImage, this->VolumePixels))
  {
    std::fill(this->VolumePixels, this->VolumePixels + 4, 0);
    this->VolumePixels[1] = this->VolumePixels[3] = -1;
  }
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCasterRays::Chord(int i, int j, double& te, double& tx) const
{
  te = 0.0;
  tx = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
  {
    const double o = this->O[a] + i * this->EX[a] + j * this->EY[a];
    const double lo = this->ChordLo[a], hi = this->ChordHi[a];
    if (this->Still[a])
    {
      tx = (o >= lo && o <= hi) ? tx : -1.0;
      continue;
    }
    const double t1 = (lo - o) * this->InvD[a], t2 = (hi - o) * this->InvD[a];
    te = std::max(te, std::min(t1, t2));
    tx = std::min(tx, std::max(t1, t2));
  }
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCasterRays::SetPiece(const double wholeLo[3],
  const double wholeHi[3],
  const int ownedLo[3],
  const int ownedHi[3],
  const int extent[3],
  vtkMatrix4x4* toStructured,
  vtkCameraRayModel* model)
{
  this->Piece = true;
  double o00[3], o10[3], o01[3], d[3];
  model->GetPixelRay(0, 0, o00, d);
  model->GetPixelRay(1, 0, o10, d);
  model->GetPixelRay(0, 1, o01, d);
  auto toGrid = [&](const double w[3], double g[3])
  {
    const double in[4] = { w[0], w[1], w[2], 1.0 };
    double out[4];
    toStructured->MultiplyPoint(in, out);
    std::copy(out, out + 3, g);
  };
  double g10[3], g01[3];
  toGrid(o00, this->StructuredO);
  toGrid(o10, g10);
  toGrid(o01, g01);
  vtkMath::Subtract(g10, this->StructuredO, this->StructuredEX);
  vtkMath::Subtract(g01, this->StructuredO, this->StructuredEY);
  for (int a = 0; a < 3; ++a)
  {
    this->ChordLo[a] = wholeLo[a];
    this->ChordHi[a] = wholeHi[a];
    this->OwnedLo[a] = static_cast<double>(ownedLo[a]) + extent[a];
    this->OwnedHi[a] = static_cast<double>(ownedHi[a]) + extent[a];
    // A face of the whole volume is nobody else's: the chord ends there.
    this->Shared[2 * a] = ownedLo[a] > wholeLo[a];
    this->Shared[2 * a + 1] = ownedHi[a] < wholeHi[a];
  }
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCasterRays::OwnedSamples(int i, int j, double phase, double range[2]) const
{
  const double infinity = std::numeric_limits<double>::infinity();
  range[0] = -infinity;
  range[1] = infinity;
  if (!this->Piece)
  {
    return;
  }
  // The ray's part in the owned box, [ta, tb), t from the camera plane.
  double ta = -infinity, tb = infinity;
  for (int a = 0; a < 3; ++a)
  {
    const double o = this->StructuredO[a] + i * this->StructuredEX[a] + j * this->StructuredEY[a];
    const bool sharedLo = this->Shared[2 * a], sharedHi = this->Shared[2 * a + 1];
    if (this->Still[a])
    {
      // A ray in a shared face belongs to the piece above it.
      if ((sharedLo && o < this->OwnedLo[a]) || (sharedHi && o >= this->OwnedHi[a]))
      {
        range[0] = infinity;
        return;
      }
      continue;
    }
    const double tLo = (this->OwnedLo[a] - o) * this->InvD[a];
    const double tHi = (this->OwnedHi[a] - o) * this->InvD[a];
    const bool up = this->D[a] > 0.0;
    if (up ? sharedLo : sharedHi)
    {
      ta = std::max(ta, up ? tLo : tHi);
    }
    if (up ? sharedHi : sharedLo)
    {
      tb = std::min(tb, up ? tHi : tLo);
    }
  }
  // Sample n of this piece lies at phase + (n + SkippedSteps) step from the camera plane.
  if (ta > -infinity)
  {
    range[0] = std::ceil((ta - phase) / this->Step) - this->SkippedSteps;
  }
  if (tb < infinity)
  {
    range[1] = std::ceil((tb - phase) / this->Step) - this->SkippedSteps;
  }
}

//------------------------------------------------------------------------------
bool vtkObjectOrderRayCasterRays::Rectangle(const double lo[3],
  const double hi[3],
  const int clip[4],
  int rect[4]) const
{
  double c[3], h[3];
  for (int a = 0; a < 3; ++a)
  {
    c[a] = 0.5 * (lo[a] + hi[a]) - this->O[a];
    h[a] = 0.5 * (hi[a] - lo[a]);
  }
  const double u = vtkMath::Dot(this->Inverse[0], c), v = vtkMath::Dot(this->Inverse[1], c);
  const double hu = std::abs(this->Inverse[0][0]) * h[0] + std::abs(this->Inverse[0][1]) * h[1] +
    std::abs(this->Inverse[0][2]) * h[2] + 1e-6;
  const double hv = std::abs(this->Inverse[1][0]) * h[0] + std::abs(this->Inverse[1][1]) * h[1] +
    std::abs(this->Inverse[1][2]) * h[2] + 1e-6;
  // Clipped in double to [lo - 1, hi + 1] before the conversion, which would overflow under
  // extreme zoom; the bounds are integers, so rounding after clipping is the same.
  // NaN (from a degenerate frame) counts as the whole clip rectangle: conservative.
  auto ceilIn = [](double x, int lo, int hi)
  {
    x = std::isnan(x) ? lo : std::min(std::max(x, lo - 1.0), hi + 1.0);
    const int n = static_cast<int>(x); // truncates towards 0
    return n + (n < x ? 1 : 0);
  };
  auto floorIn = [](double x, int lo, int hi)
  {
    x = std::isnan(x) ? hi : std::min(std::max(x, lo - 1.0), hi + 1.0);
    const int n = static_cast<int>(x);
    return n - (n > x ? 1 : 0);
  };
  rect[0] = std::max(ceilIn(u - hu, clip[0], clip[1]), clip[0]);
  rect[1] = std::min(floorIn(u + hu, clip[0], clip[1]), clip[1]);
  rect[2] = std::max(ceilIn(v - hv, clip[2], clip[3]), clip[2]);
  rect[3] = std::min(floorIn(v + hv, clip[2], clip[3]), clip[3]);
  return rect[0] <= rect[1] && rect[2] <= rect[3];
}
