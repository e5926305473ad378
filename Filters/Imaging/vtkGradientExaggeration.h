// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkGradientExaggeration
 * @brief   unit normals of a scalar volume with their deviation from the local mean exaggerated
 *
 * Exaggerated shading as used by Guetat et al. 2010 ("Pre-integrated volume rendering with
 * non-linear gradient interpolation", section 4, line 99 of its text): each
 * voxel's normal N is replaced by
 *
 *   N' = N + eps (N - N_m),
 *
 * N_m the mean normal over a k x k x k neighbourhood (the paper uses eps = 1, k = 5). The angle
 * between a normal and its neighbourhood's mean grows, so small-scale detail shows more in the
 * shading. Per voxel:
 *
 *   G   = gradient of the scalar field in world units (spacing respected)
 *   N   = G / |G|, or 0 where |G| is below the zero-gradient threshold (below)
 *   M   = sum of N over the k^3 box centred on the voxel, truncated at the volume's borders
 *   N_m = M / |M|, or N where M = 0
 *   N'  = 0 where N = 0, else N + eps (N - N_m)
 *   out = N' / |N'|  (|N'| >= 1 for unit N and N_m, so it never vanishes)
 *
 * Averaging unit normals rather than raw gradients makes every neighbour count alike, so a strong
 * edge does not dominate N_m: the operator rotates normals, it does not rescale them.
 *
 * Gradients:
 * - CENTRAL_DIFFERENCE: (v[i+1] - v[i-1]) / (2 spacing), as vtkImageGradient and VTK's GPU ray
 *   caster. At a border, and beside a NaN voxel, the one-sided difference (v[1] - v[0]) /
 *   spacing; vtkImageGradient with HandleBoundaries on repeats the edge value instead, which
 *   halves that component (a linear field would get tilted border normals). Along an axis with
 *   one point the component is 0.
 * - SOBEL: vtkImageSobel3D's 3 x 3 x 3 operator (weights 2 on the axis line, 1 beside it, 0.586
 *   diagonally; transverse neighbours outside the volume repeat the edge, as VTK does), with
 *   each line's difference one-sided at a border or beside a NaN voxel as above.
 *
 * The zero-gradient threshold: a normal is 0 where |G| * (smallest spacing) <= 1e-12 * (finite
 * data range), i.e. where the value changes by at most a 1e-12th of the range across the
 * finest cell; a constant volume gives all-zero normals. Zero normals add nothing to their
 * neighbours' means.
 *
 * Non-finite values (NaN, +-Inf) are missing data: such a voxel gets a zero normal, and its
 * neighbours' differences skip it (one-sided, as at a border; a component without any finite
 * neighbour along its axis is 0), so it does not spread.
 *
 * Output: the input image (shallow copy, its scalars and other arrays passed through) with a
 * 3-component float point array named OutputArrayName, unit vectors or 0. Normals are in the
 * image's axis frame: the direction matrix (VTK 9.1 image orientation) is not applied, as by
 * vtkImageGradient. Pieces and sub-extents can be requested: the filter asks for the extent
 * grown by the box radius plus one (the gradient's reach), as more ghost levels for a piece, and
 * gives the same normals there as for the whole volume, except that the zero-gradient threshold
 * uses the range of the data it was given.
 *
 * Cost: O(number of voxels), independent of k (a running-sum box filter along each axis in
 * turn), in vtkSMPTools threads; the gradient is computed twice instead of being stored, so the
 * only large buffer is the output array, which holds the box sums (as floats) in between.
 * N_m thus carries a relative rounding error of about 1e-7, which eps multiplies: with eps far
 * above 1e4 the output is rounding noise where N is close to N_m. eps = 0 and k = 1 skip the
 * box sums and give the normalised gradient exactly. Progress events come between chunks of
 * work, on the calling thread, and AbortExecute is honoured there (the output then has no
 * normals array).
 *
 * Bad input or settings are reported through vtkErrorMacro with an empty output: no input
 * array, a cell array, more than one component, a point count that does not match the grid, an
 * empty image, a zero or non-finite spacing, an even or non-positive NeighborhoodSize, a negative
 * or non-finite Epsilon, an empty OutputArrayName or one equal to the input array's name.
 *
 * @sa vtkImageGradient vtkImageSobel3D vtkImageNormalize
 */
#ifndef vtkGradientExaggeration_h
#define vtkGradientExaggeration_h

#include "hovrFiltersImagingModule.h" // For export macro
#include "vtkImageAlgorithm.h"

class HOVRFILTERSIMAGING_EXPORT vtkGradientExaggeration : public vtkImageAlgorithm
{
public:
  static vtkGradientExaggeration* New();
  vtkTypeMacro(vtkGradientExaggeration, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum GradientMethods
  {
    CENTRAL_DIFFERENCE = 0,
    SOBEL = 1
  };

  ///@{
  /**
   * Amplitude eps of the exaggeration, finite and >= 0; 0 gives the normalised gradients.
   * Initial value is 1.0 (the paper's).
   */
  vtkSetMacro(Epsilon, double);
  vtkGetMacro(Epsilon, double);
  ///@}

  ///@{
  /**
   * Edge k of the cubic neighbourhood, in voxels, odd and >= 1: a k x k x k box centred on the
   * voxel (itself included), truncated at the volume's borders. 1 makes N_m = N, so the output
   * is the normalised gradient whatever Epsilon. Initial value is 5 (the paper's).
   */
  vtkSetMacro(NeighborhoodSize, int);
  vtkGetMacro(NeighborhoodSize, int);
  ///@}

  ///@{
  /**
   * Gradient operator: CENTRAL_DIFFERENCE or SOBEL (see the class description). Initial value
   * is CENTRAL_DIFFERENCE.
   */
  vtkSetClampMacro(GradientMethod, int, CENTRAL_DIFFERENCE, SOBEL);
  vtkGetMacro(GradientMethod, int);
  void SetGradientMethodToCentralDifference() { this->SetGradientMethod(CENTRAL_DIFFERENCE); }
  void SetGradientMethodToSobel() { this->SetGradientMethod(SOBEL); }
  const char* GetGradientMethodAsString();
  ///@}

  ///@{
  /**
   * Name of the output normals array. Initial value is "ExaggeratedNormals".
   */
  vtkSetStringMacro(OutputArrayName);
  vtkGetStringMacro(OutputArrayName);
  ///@}

protected:
  vtkGradientExaggeration();
  ~vtkGradientExaggeration() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double Epsilon = 1.0;
  int NeighborhoodSize = 5;
  int GradientMethod = CENTRAL_DIFFERENCE;
  char* OutputArrayName = nullptr;

private:
  vtkGradientExaggeration(const vtkGradientExaggeration&) = delete;
  void operator=(const vtkGradientExaggeration&) = delete;
};

#endif
