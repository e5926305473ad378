// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkGridRayTraversal.h"

#include <algorithm>
#include <cmath>
#include <limits>

//------------------------------------------------------------------------------
bool vtkGridRayTraversal::ClipToBox(const double lo[3],
  const double hi[3],
  const double origin[3],
  const double direction[3],
  double& tmin,
  double& tmax)
{
  for (int a = 0; a < 3; ++a)
  {
    if (direction[a] == 0.0)
    {
      // Parallel to this slab: inside it for every t or never.
      if (origin[a] < lo[a] || origin[a] > hi[a])
      {
        return false;
      }
      continue;
    }
    double ta = (lo[a] - origin[a]) / direction[a];
    double tb = (hi[a] - origin[a]) / direction[a];
    if (ta > tb)
    {
      std::swap(ta, tb);
    }
    tmin = std::max(tmin, ta);
    tmax = std::min(tmax, tb);
  }
  return tmin < tmax;
}

//------------------------------------------------------------------------------
bool vtkGridRayTraversal::Initialize(const int dims[3],
  const double origin[3],
  const double direction[3],
  double tmin,
  double tmax)
{
  this->Done = true;
  double hi[3];
  const double lo[3] = { 0.0, 0.0, 0.0 };
  for (int a = 0; a < 3; ++a)
  {
    if (dims[a] < 2)
    {
      return false;
    }
    hi[a] = dims[a] - 1.0;
  }
  if (!vtkGridRayTraversal::ClipToBox(lo, hi, origin, direction, tmin, tmax))
  {
    return false;
  }
  this->TEntry = tmin;
  this->TExit = tmax;
  this->TCurrent = tmin;
  // The first cell is the one containing a point just past the entry; clamping keeps points
  // on the far faces inside the last cell.
  const double tInside = tmin + 1e-9 * std::max(1.0, tmax - tmin);
  for (int a = 0; a < 3; ++a)
  {
    const double p = origin[a] + tInside * direction[a];
    this->Cell[a] = std::min(std::max(static_cast<int>(std::floor(p)), 0), dims[a] - 2);
    this->LastCell[a] = dims[a] - 2;
    if (direction[a] > 0.0)
    {
      this->Step[a] = 1;
      this->TMax[a] = (this->Cell[a] + 1.0 - origin[a]) / direction[a];
      this->TDelta[a] = 1.0 / direction[a];
    }
    else if (direction[a] < 0.0)
    {
      this->Step[a] = -1;
      this->TMax[a] = (this->Cell[a] - origin[a]) / direction[a];
      this->TDelta[a] = -1.0 / direction[a];
    }
    else
    {
      this->Step[a] = 0;
      this->TMax[a] = std::numeric_limits<double>::infinity();
      this->TDelta[a] = std::numeric_limits<double>::infinity();
    }
  }
  this->Done = false;
  return true;
}

//------------------------------------------------------------------------------
bool vtkGridRayTraversal::Next(int cell[3], double& t0, double& t1)
{
  if (this->Done)
  {
    return false;
  }
  int axis = 0;
  if (this->TMax[1] < this->TMax[axis])
  {
    axis = 1;
  }
  if (this->TMax[2] < this->TMax[axis])
  {
    axis = 2;
  }
  cell[0] = this->Cell[0];
  cell[1] = this->Cell[1];
  cell[2] = this->Cell[2];
  t0 = this->TCurrent;
  t1 = std::min(std::max(this->TMax[axis], t0), this->TExit);
  this->TCurrent = t1;
  if (t1 >= this->TExit)
  {
    this->Done = true;
    return true;
  }
  this->Cell[axis] += this->Step[axis];
  this->TMax[axis] += this->TDelta[axis];
  if (this->Cell[axis] < 0 || this->Cell[axis] > this->LastCell[axis])
  {
    this->Done = true;
  }
  return true;
}
