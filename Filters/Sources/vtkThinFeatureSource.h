// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkThinFeatureSource
 * @brief   a volume of sheets and tubes thinner than a voxel, where sampled isosurfaces fail
 *
 * Point scalars f = max over features of max(0, 1 - d / Thickness), d being the distance of
 * the point to a feature: three planar sheets and four straight tubes (lines), all oblique
 * to the grid, fixed so that images are reproducible. With Thickness below one voxel only
 * the points nearest a feature are non-zero, so the trilinear field rises above an isovalue
 * such as 0.5 in films and threads a fraction of a voxel thick: a ray caster that samples at
 * a fixed step steps over many of them, the analytic first hit finds them all (the
 * thin-features volume of presets/bench/analytic.json).
 *
 * Spacing 1, origin 0, extent 0..dims-1; float scalars "ThinFeatures" in [0, 1]. Any
 * sub-extent can be requested (a piece of a parallel pipeline computes only its own points).
 */
#ifndef vtkThinFeatureSource_h
#define vtkThinFeatureSource_h

#include "hovrFiltersSourcesModule.h" // For export macro
#include "vtkImageAlgorithm.h"

class HOVRFILTERSSOURCES_EXPORT vtkThinFeatureSource : public vtkImageAlgorithm
{
public:
  static vtkThinFeatureSource* New();
  vtkTypeMacro(vtkThinFeatureSource, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Points along each axis, at least 2. Initial value is 64 x 64 x 64.
   */
  vtkSetVector3Macro(Dimensions, int);
  vtkGetVector3Macro(Dimensions, int);
  ///@}

  ///@{
  /**
   * Half-width of the features' tent profile in voxels, positive. Initial value is 0.7.
   */
  vtkSetClampMacro(Thickness, double, 1e-3, 1e3);
  vtkGetMacro(Thickness, double);
  ///@}

  /**
   * The field at a point given in voxel coordinates of a grid of the given dimensions.
   */
  static double Evaluate(const double point[3], const int dims[3], double thickness);

protected:
  vtkThinFeatureSource();
  ~vtkThinFeatureSource() override = default;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  void ExecuteDataWithInformation(vtkDataObject* output, vtkInformation* outInfo) override;

  int Dimensions[3] = { 64, 64, 64 };
  double Thickness = 0.7;

private:
  vtkThinFeatureSource(const vtkThinFeatureSource&) = delete;
  void operator=(const vtkThinFeatureSource&) = delete;
};

#endif
