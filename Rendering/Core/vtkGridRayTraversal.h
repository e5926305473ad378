// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkGridRayTraversal
 * @brief   visits, in order, the cells of a regular grid that a ray crosses
 *
 * A lightweight value class (not a vtkObject, not wrapped) for inner loops: the 3D digital
 * differential analyser of Amanatides and Woo in continuous index space, where the points of
 * the grid sit at integer coordinates 0..dims-1 and cell (i, j, k) is the unit cube above
 * point (i, j, k). The ray is p(t) = origin + t direction; direction need not be normalised,
 * so t can be any parameter (hovr uses world distance). Rays along grid axes and rays through
 * edges or corners are handled: a zero component never steps, ties step one axis at a time
 * and yield zero-length segments that callers may skip.
 */
#ifndef vtkGridRayTraversal_h
#define vtkGridRayTraversal_h

#include "hovrRenderingCoreModule.h" // For export macro

class HOVRRENDERINGCORE_EXPORT vtkGridRayTraversal
{
public:
  /**
   * Clip the ray to the box [0, dims-1]^3 intersected with [tmin, tmax] and find the first
   * cell. Returns false when the ray misses the box or the grid has fewer than 2 points on an
   * axis (no cells).
   */
  bool Initialize(const int dims[3],
    const double origin[3],
    const double direction[3],
    double tmin,
    double tmax);

  /**
   * The next cell and the parameter interval [t0, t1] of the ray inside it. Returns false
   * after the last cell.
   */
  bool Next(int cell[3], double& t0, double& t1);

  ///@{
  /**
   * Parameter interval of the ray inside the grid's box, valid after Initialize().
   */
  double GetEntry() const { return this->TEntry; }
  double GetExit() const { return this->TExit; }
  ///@}

  /**
   * Clip a ray against the box [lo, hi]: on success tmin and tmax are narrowed to the
   * interval inside the box. Shared by every hovr ray caster.
   */
  static bool ClipToBox(const double lo[3],
    const double hi[3],
    const double origin[3],
    const double direction[3],
    double& tmin,
    double& tmax);

private:
  int Cell[3] = { 0, 0, 0 };
  int Step[3] = { 0, 0, 0 };
  int LastCell[3] = { 0, 0, 0 };
  double TMax[3] = { 0, 0, 0 };
  double TDelta[3] = { 0, 0, 0 };
  double TCurrent = 0.0;
  double TEntry = 0.0;
  double TExit = 0.0;
  bool Done = true;
};

#endif
