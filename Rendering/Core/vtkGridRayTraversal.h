// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkGridRayTraversal
 * @brief   visits, in order, the cells of a regular grid that a ray crosses
 *
 * A lightweight value class (not a vtkObject, not wrapped) for inner loops, in continuous index
 * space: the points of the grid sit at integer coordinates 0..dims-1 and cell (i, j, k) is the
 * unit cube above point (i, j, k). The ray is p(t) = origin + t direction; direction need not
 * be normalised, so t can be any parameter (hovr uses world distance).
 *
 * The walk is the integer-based traversal of Jozsa, Toth and Csebfalvi ("Analytic isosurface
 * rendering and maximum intensity projection on the GPU", section 7): the only state that
 * changes is the integer coordinate of the next plane crossing along each axis; the parameter
 * of a crossing is recomputed from it and the constant entry point in every step,
 *   t_next[a] = t_entry + (next[a] - entry[a]) / direction[a],
 * so rounding errors do not accumulate along the ray, unlike the incremental digital
 * differential analyser of Amanatides and Woo, whose t_max[a] += t_delta[a] adds one rounding
 * per step (TestGridRayTraversal measures both in float on a 256^3 grid). Every axis whose
 * crossing is the nearest steps at once, so a ray through an edge or a corner goes straight
 * to the diagonal cell, with no zero-length segment; a zero direction component never steps.
 *
 * vtkGridRayTraversalT<float> mirrors the GLSL of hovr's analytic ray caster;
 * vtkGridRayTraversal (double) serves the CPU reference.
 */
#ifndef vtkGridRayTraversal_h
#define vtkGridRayTraversal_h

#include <algorithm> // For std::min
#include <cmath>     // For std::floor
#include <limits>    // For infinity

template <typename Real>
class vtkGridRayTraversalT
{
public:
  /**
   * Clip the ray to the box [0, dims-1]^3 intersected with [tmin, tmax] and find the first
   * cell. Returns false when the ray misses the box, its origin or direction is not finite, or
   * the grid has fewer than 2 points on an axis (no cells).
   */
  bool Initialize(const int dims[3],
    const Real origin[3],
    const Real direction[3],
    Real tmin,
    Real tmax)
  {
    this->Done = true;
    Real lo[3] = { 0, 0, 0 }, hi[3];
    for (int a = 0; a < 3; ++a)
    {
      // A non-finite ray meets no cell (and would give no integer cell index).
      if (dims[a] < 2 || !std::isfinite(origin[a]) || !std::isfinite(direction[a]))
      {
        return false;
      }
      hi[a] = static_cast<Real>(dims[a] - 1);
      this->LastCell[a] = dims[a] - 2;
    }
    if (!vtkGridRayTraversalT::ClipToBox(lo, hi, origin, direction, tmin, tmax))
    {
      return false;
    }
    this->TEntry = tmin;
    this->TExit = tmax;
    this->TCurrent = tmin;
    for (int a = 0; a < 3; ++a)
    {
      // Clamped so that an entry one rounding outside its face starts in the first cell.
      this->Entry[a] = std::min(std::max(origin[a] + tmin * direction[a], lo[a]), hi[a]);
      this->Direction[a] = direction[a];
      this->Crossed[a] = false;
      // The previous crossing: the entry rounded against the direction; the next one a step on.
      if (direction[a] > 0)
      {
        this->Step[a] = 1;
        this->Next[a] = static_cast<int>(std::floor(this->Entry[a])) + 1;
        this->InverseDirection[a] = 1 / direction[a];
      }
      else if (direction[a] < 0)
      {
        this->Step[a] = -1;
        this->Next[a] = static_cast<int>(std::ceil(this->Entry[a])) - 1;
        this->InverseDirection[a] = 1 / direction[a];
      }
      else
      {
        this->Step[a] = 0;
        this->Next[a] = static_cast<int>(std::floor(this->Entry[a]));
        this->InverseDirection[a] = 0;
      }
    }
    this->Done = false;
    return true;
  }

  /**
   * The next cell and the parameter interval [t0, t1] of the ray inside it. Returns false
   * after the last cell.
   */
  bool NextCell(int cell[3], Real& t0, Real& t1)
  {
    if (this->Done)
    {
      return false;
    }
    Real crossing[3];
    Real nearest = this->TExit;
    for (int a = 0; a < 3; ++a)
    {
      crossing[a] = this->CrossingParameter(a);
      nearest = std::min(nearest, crossing[a]);
      // The cell lies behind the next crossing; a still axis keeps the entry's cell.
      const int c = this->Step[a] > 0 ? this->Next[a] - 1 : this->Next[a];
      cell[a] = std::min(std::max(c, 0), this->LastCell[a]);
    }
    t0 = this->TCurrent;
    t1 = std::max(nearest, t0);
    // Crossing a face of the box ends the walk there, even one rounding short of TExit.
    bool leaves = t1 >= this->TExit;
    for (int a = 0; a < 3; ++a)
    {
      leaves = leaves ||
        (crossing[a] <= nearest &&
          (this->Step[a] > 0 ? this->Next[a] > this->LastCell[a] : this->Next[a] <= 0));
    }
    if (leaves)
    {
      t1 = std::max(this->TExit, t0);
      this->TCurrent = t1;
      this->Done = true;
      this->Crossed[0] = this->Crossed[1] = this->Crossed[2] = false;
      return true;
    }
    this->TCurrent = t1;
    for (int a = 0; a < 3; ++a)
    {
      // Every axis tied for the nearest crossing steps: edges and corners go diagonally.
      this->Crossed[a] = crossing[a] <= nearest;
      this->Next[a] += this->Crossed[a] ? this->Step[a] : 0;
    }
    return true;
  }

  /**
   * The point where the ray leaves the cell last returned by NextCell(), at its t1: the
   * coordinates of the planes it crosses there are exact integers, the others one rounding
   * away from p(t1).
   */
  void GetExitPoint(Real point[3]) const
  {
    for (int a = 0; a < 3; ++a)
    {
      point[a] = this->Crossed[a]
        ? static_cast<Real>(this->Next[a] - this->Step[a])
        : this->Entry[a] + (this->TCurrent - this->TEntry) * this->Direction[a];
    }
  }

  ///@{
  /**
   * Parameter interval of the ray inside the grid's box, valid after Initialize().
   */
  Real GetEntry() const { return this->TEntry; }
  Real GetExit() const { return this->TExit; }
  ///@}

  /**
   * Clip a ray against the box [lo, hi]: on success tmin and tmax are narrowed to the
   * interval inside the box. Shared by every hovr ray caster.
   */
  static bool ClipToBox(const Real lo[3],
    const Real hi[3],
    const Real origin[3],
    const Real direction[3],
    Real& tmin,
    Real& tmax)
  {
    for (int a = 0; a < 3; ++a)
    {
      if (direction[a] == 0)
      {
        // Parallel to this slab: inside it for every t or never.
        if (origin[a] < lo[a] || origin[a] > hi[a])
        {
          return false;
        }
        continue;
      }
      Real ta = (lo[a] - origin[a]) / direction[a];
      Real tb = (hi[a] - origin[a]) / direction[a];
      if (ta > tb)
      {
        std::swap(ta, tb);
      }
      tmin = std::max(tmin, ta);
      tmax = std::min(tmax, tb);
    }
    return tmin < tmax;
  }

private:
  // Parameter of the next crossing along axis a, from the constant entry point and the integer
  // plane coordinate alone (section 7): one multiplication, no accumulated state.
  Real CrossingParameter(int a) const
  {
    return this->Step[a] == 0 ? std::numeric_limits<Real>::infinity()
                              : this->TEntry +
        (static_cast<Real>(this->Next[a]) - this->Entry[a]) * this->InverseDirection[a];
  }

  int Next[3] = { 0, 0, 0 };
  int Step[3] = { 0, 0, 0 };
  int LastCell[3] = { 0, 0, 0 };
  Real Entry[3] = { 0, 0, 0 };
  Real Direction[3] = { 0, 0, 0 };
  Real InverseDirection[3] = { 0, 0, 0 };
  bool Crossed[3] = { false, false, false };
  Real TCurrent = 0;
  Real TEntry = 0;
  Real TExit = 0;
  bool Done = true;
};

/**
 * The double-precision traversal of the CPU reference.
 */
class vtkGridRayTraversal : public vtkGridRayTraversalT<double>
{
public:
  bool Next(int cell[3], double& t0, double& t1) { return this->NextCell(cell, t0, t1); }
};

#endif
