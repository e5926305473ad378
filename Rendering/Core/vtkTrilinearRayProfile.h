// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkTrilinearRayProfile
 * @brief   the cubic that a trilinearly interpolated scalar follows along a ray in one cell
 *
 * Inside a cell, the trilinear interpolant restricted to the ray u(t) = u0 + t v (local cell
 * coordinates in [0, 1]^3) is a cubic s(t) = c3 t^3 + c2 t^2 + c1 t + c0. A lightweight value
 * class (not a vtkObject, not wrapped) for inner loops of CPU ray casters.
 */
#ifndef vtkTrilinearRayProfile_h
#define vtkTrilinearRayProfile_h

#include "hovrRenderingCoreModule.h" // For export macro

class HOVRRENDERINGCORE_EXPORT vtkTrilinearRayProfile
{
public:
  /**
   * Set the profile from the 8 corner values, indexed i + 2 j + 4 k, the entry point u0 in
   * local cell coordinates and the direction v in local units per unit of t.
   */
  void Set(const double corner[8], const double u0[3], const double v[3]);

  /**
   * Set the profile over a unit parameter interval from four samples at t = 0, 1/3, 2/3 and
   * 1 (Eq. 3-4 of Jozsa, Toth and Csebfalvi): how hovr's analytic GPU ray caster builds it
   * from trilinear samples; mirrored in hovrAnalytic.glsl.
   */
  void SetFromSamples(double f1, double f2, double f3, double f4);

  /**
   * Parameters t in (0, length) where ds/dt = 0 (Eq. 5-6), in increasing order; returns
   * their number (0, 1 or 2). Degenerate cases: a quadratic or linear profile has at most
   * one, a constant one none; a double root of the derivative (an inflection with zero
   * slope) is returned once.
   */
  int GetCriticalPoints(double length, double t[2]) const;

  /**
   * Smallest and largest s over [0, length]: the end points and the interior extrema
   * (section 6; the analytic maximum and minimum intensity projection of section 9).
   */
  void GetRange(double length, double& smin, double& smax) const;

  /**
   * The first t in [0, length] with s(t) = value, if any. The interval is cut at the
   * critical points into pieces on which s is monotone; the first piece whose end values
   * bracket the value (or touch it) is bisected to full double precision. A touching
   * (tangent) profile counts as a hit only where s equals the value exactly.
   */
  bool FindFirstCrossing(double value, double length, double& t) const;

  /**
   * s(t).
   */
  double Evaluate(double t) const
  {
    return ((this->C[3] * t + this->C[2]) * t + this->C[1]) * t + this->C[0];
  }

  /**
   * ds/dt at t.
   */
  double Derivative(double t) const
  {
    return (3.0 * this->C[3] * t + 2.0 * this->C[2]) * t + this->C[1];
  }

  /**
   * Largest |ds/dt| over [0, length]: a bound on how fast the scalar can change there.
   */
  double GetMaximumSlope(double length) const;

  /**
   * Coefficients c0..c3.
   */
  const double* GetCoefficients() const { return this->C; }

private:
  double C[4] = { 0, 0, 0, 0 };
};

#endif
