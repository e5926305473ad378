// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkCurvedShellSource
 * @brief   thin, smoothly curved shells: a test volume for shaded volume rendering
 *
 * Point scalars f(p) = max over shells k of exp(-(d_k(p) / w)^2), w = ShellThickness, so f is
 * 1 on a shell's surface and 1/e at the distance w from it. Shell k is a wobbled sphere: with
 * q = p - c_k, rho = |q| and n = q / rho, its surface is rho = r_k(n),
 *   r_k(n) = R_k (1 + a W_k(n)),   W_k(n) = 2 n_x n_y n_z (4 n_{A_k}^2 - 3),
 * a = Wobble. In spherical coordinates about the polar axis A_k (theta from that axis, phi in
 * the plane of the other two axes in cyclic order) W_k = cos(3 theta) sin^2(theta) sin(2 phi):
 * the sin^2(theta) factor makes the wobble vanish at the poles, so the surface is smooth
 * there as everywhere else, and |W_k| <= 1 keeps the radius within R_k (1 +- a). The distance
 * of p to the tangent plane of the surface at p's radial projection c_k + r_k(n) n,
 *   t_k = |rho - r_k(n)| / sqrt(1 + (R_k a |grad_t W_k(n)| / r_k(n))^2),
 * grad_t W_k being the gradient of W_k on the unit sphere, is the Euclidean distance to first
 * order near the surface, where the profile is visible, and exactly 0 on it. Far from the
 * surface (near the centre) the slope of the wobble makes t_k too small, so d_k is the larger
 * of t_k and the distance to the spherical layer R_k (1 - a) <= rho <= R_k (1 + a) that holds
 * the surface.
 *
 * The four shells are fixed so that images are reproducible (centre c_k, radius R_k, polar
 * axis A_k):
 *   (0, 0, 0), 0.5, z;   (0, 0, 0.05), 0.8, x;   (0.35, 0.3, -0.3), 0.3, y;
 *   (-0.4, -0.3, 0.35), 0.25, z.
 * At the initial wobble the second holds the first; the last two cut through the first. A
 * ray crosses several shells, each a few voxels thick, and the data gradient, which shading
 * uses as the normal, turns through half a turn across each of them: the surfaces of a CT
 * scan, but analytic.
 *
 * The grid spans [-1, 1]^3 with Dimensions points per axis (spacing 2 / (n - 1), origin -1);
 * float scalars "CurvedShells" in [0, 1]. Dimensions below 2, a ShellThickness that is not a
 * positive finite number or a Wobble that is not a number are an error and give an empty
 * output. Any sub-extent can be requested (a piece of a parallel pipeline computes only its
 * own points, the same values as in the whole volume).
 */
#ifndef vtkCurvedShellSource_h
#define vtkCurvedShellSource_h

#include "hovrFiltersSourcesModule.h" // For export macro
#include "vtkCubeFieldSource.h"

class HOVRFILTERSSOURCES_EXPORT vtkCurvedShellSource : public vtkCubeFieldSource
{
public:
  static vtkCurvedShellSource* New();
  vtkTypeMacro(vtkCurvedShellSource, vtkCubeFieldSource);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Width w of the shells' Gaussian profile in world units, positive and finite. Initial
   * value is 0.04 (about 2.5 voxels at the initial dimensions).
   */
  vtkSetMacro(ShellThickness, double);
  vtkGetMacro(ShellThickness, double);
  ///@}

  ///@{
  /**
   * Relative amplitude a of the radius' wobble, clamped to [0, 0.5]: 0 gives spheres.
   * Initial value is 0.15.
   */
  vtkSetClampMacro(Wobble, double, 0.0, 0.5);
  vtkGetMacro(Wobble, double);
  ///@}

  /**
   * The field at a point (x, y, z) for the given thickness and wobble.
   */
  static double Evaluate(const double point[3], double thickness, double wobble);

protected:
  vtkCurvedShellSource() = default;
  ~vtkCurvedShellSource() override = default;

  const char* GetFieldName() override { return "CurvedShells"; }
  bool CheckFieldSettings() override;
  double EvaluateField(const double point[3]) override;

  double ShellThickness = 0.04;
  double Wobble = 0.15;

private:
  vtkCurvedShellSource(const vtkCurvedShellSource&) = delete;
  void operator=(const vtkCurvedShellSource&) = delete;
};

#endif
