// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkVolumeReferenceIntegrator
 * @brief   ground truth: the volume-rendering integral through the trilinear field, on the CPU
 *
 * Computes, in double precision and for every pixel ray of vtkCameraRayModel, the emission-
 * absorption integral C = int c(s(t)) tau(s(t)) exp(-int_0^t tau) dt through the trilinearly
 * interpolated point scalars of the input image, with the transfer-function meaning of
 * vtkVolumeTransferFunctionSampler. This is the yardstick every hovr method is measured by.
 *
 * How: the ray is walked cell by cell (vtkGridRayTraversal). Inside a cell the scalar is an
 * exact cubic in t (vtkTrilinearRayProfile); the cell segment is cut into pieces such that
 * the scalar changes by at most ScalarTolerance * (narrowest transfer-function feature among
 * those the piece's values can meet) per piece, from a bound on |ds/dt| over the cell: a
 * narrow feature makes pieces fine only where the profile comes near it. Each piece
 * is integrated with colour and extinction of its midpoint scalar, which is exact for constant
 * pieces and converges as O(ScalarTolerance^2) otherwise (the convergence is tested). Cells whose
 * corner range has zero opacity everywhere are skipped exactly (the interpolant stays inside the
 * corner range). The walk stops when the transmittance falls below TransmittanceCutoff.
 *
 * Output: a W x H x 1 image, pixel (i, j) counted from left and bottom, with point data
 * "RGBA" (float, premultiplied: accumulated emission, alpha = 1 - transmittance) over a
 * transparent black background. Multithreaded with vtkSMPTools; fires progress events.
 *
 * Other blend modes (BlendMode, the values of vtkVolumeMapper's blend modes) give the exact
 * answers of the analytic methods of Jozsa, Toth and Csebfalvi, in double precision:
 * - ISOSURFACE: the first point of the ray where the trilinear field equals one of the
 *   volume property's isosurface values (vtkVolumeProperty::GetIsoSurfaceValues()), found
 *   with vtkTrilinearRayProfile::FindFirstCrossing in the first cell whose range holds a value.
 *   Point data "Depth" (double) is the world distance from the ray's origin (NaN on a miss);
 *   "DepthSpread" (double) the largest change of that depth, in world units, when every
 *   isovalue moves by +-IsoPerturbation of the data range (infinite where the ray would then
 *   miss or start to hit: grazing and touching rays; 0 on other misses);
 *   "RGBA" is the opaque surface: the colour transfer function at the isovalue, shaded when
 *   the property's Shade is on with a headlight along the ray (ambient + diffuse |n.v| +
 *   specular |n.v|^power, two-sided, n the exact gradient of the trilinear field).
 * - MAXIMUM_INTENSITY / MINIMUM_INTENSITY: the exact extremum of the trilinear field along the
 *   ray (cell end points and interior extrema). "MaxScalar" / "MinScalar" (double, data units;
 *   NaN where the ray misses the volume); "RGBA" as VTK's projections: colour and opacity
 *   transfer functions at the extremum, opacity taken as alpha.
 *
 * The input must be a vtkImageData with a single-component point scalar array of at least
 * 2 points along each axis; NaN scalars are transparent. Other inputs give an error and an
 * empty (transparent) image.
 */
#ifndef vtkVolumeReferenceIntegrator_h
#define vtkVolumeReferenceIntegrator_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkVolumeImageAlgorithm.h"
#include "vtkVolumeScalarView.h" // For IntegrateRays

#include <atomic> // For IntegrateRays
#include <vector> // For RayCells

class vtkVolumeShadingModel;
class vtkVolumeTransferFunctionSampler;

class HOVRRENDERINGCORE_EXPORT vtkVolumeReferenceIntegrator : public vtkVolumeImageAlgorithm
{
public:
  static vtkVolumeReferenceIntegrator* New();
  vtkTypeMacro(vtkVolumeReferenceIntegrator, vtkVolumeImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Blend modes, with the values of vtkVolumeMapper's.
   */
  enum BlendModes
  {
    COMPOSITE_BLEND = 0,
    MAXIMUM_INTENSITY_BLEND = 1,
    MINIMUM_INTENSITY_BLEND = 2,
    ISOSURFACE_BLEND = 5
  };

  ///@{
  /**
   * What is computed along each ray (see the class description). Other values give an error.
   * Initial value is COMPOSITE_BLEND.
   */
  vtkSetMacro(BlendMode, int);
  vtkGetMacro(BlendMode, int);
  void SetBlendModeToComposite() { this->SetBlendMode(COMPOSITE_BLEND); }
  void SetBlendModeToMaximumIntensity() { this->SetBlendMode(MAXIMUM_INTENSITY_BLEND); }
  void SetBlendModeToMinimumIntensity() { this->SetBlendMode(MINIMUM_INTENSITY_BLEND); }
  void SetBlendModeToIsoSurface() { this->SetBlendMode(ISOSURFACE_BLEND); }
  ///@}

  ///@{
  /**
   * Largest change of the scalar within one integration piece, as a fraction of the narrowest
   * transfer-function feature that the cell's values meet (the smallest distance between two
   * adjacent nodes whose interval overlaps the range of the cell's corners, at most the data
   * range; one piece where the functions are constant over it). Halving it divides the error
   * by about four. Initial value is 1/64.
   */
  vtkSetClampMacro(ScalarTolerance, double, 1e-6, 1.0);
  vtkGetMacro(ScalarTolerance, double);
  ///@}

  ///@{
  /**
   * Isosurface blending: the isovalue shift, as a fraction of the data range, that measures
   * how well each pixel's first hit is determined (the "DepthSpread" array). A float ray
   * caster cannot place a hit better than its spread: at tangent hits, and where the ray
   * passes within rounding of the isovalue before its hit, a shift this small moves the hit
   * far. 0 turns the measure off (spread 0). Initial value is 1e-6.
   */
  vtkSetClampMacro(IsoPerturbation, double, 0.0, 1.0);
  vtkGetMacro(IsoPerturbation, double);
  ///@}

  ///@{
  /**
   * Rays stop when the transmittance falls below this value. Initial value is 1e-7.
   */
  vtkSetClampMacro(TransmittanceCutoff, double, 0.0, 1.0);
  vtkGetMacro(TransmittanceCutoff, double);
  ///@}

  ///@{
  /**
   * The lighting of composite blending when the volume property's Shade is on: emission per
   * unit extinction is vtkVolumeShadingModel::ShadePoint() of the transfer function's colour,
   * the normal being the trilinear interpolation of per-point central differences (of the
   * neighbours one point away, one-sided at the faces: the central difference of the trilinear
   * field), normalised, and the view the pixel ray's direction reversed. VTK's GPU ray caster
   * reaches one texture step of 1/(n - 1) either side, n/(n - 1) points on n points: its
   * normals differ slightly (vtkPreIntegrationRayCaster::GradientOperator models both). Integration
   * pieces are then also fine enough for the normal to turn by at most ScalarTolerance * 4 /
   * sqrt(n) radians per piece (n the specular power: the lobe's width). nullptr (the initial value)
   * uses a model made from the property's coefficients with VTK's default lighting: a white
   * headlight, both sides lit, the lobe.
   */
  virtual void SetShadingModel(vtkVolumeShadingModel*);
  vtkGetObjectMacro(ShadingModel, vtkVolumeShadingModel);
  ///@}

  ///@{
  /**
   * Composite shading: the point array of 3-component vectors whose trilinear interpolation,
   * normalised, is the normal (as vtkPreIntegrationVolumeMapper::NormalArrayName), instead of
   * the gradient; in world units (the data's coordinates). nullptr or empty: the gradient.
   * Initial value is nullptr.
   */
  vtkSetStringMacro(NormalArrayName);
  vtkGetStringMacro(NormalArrayName);
  ///@}

  ///@{
  /**
   * Integrate only a random sample of the pixels, this fraction of them (at least one pixel),
   * drawn with PixelSeed: the other pixels hold NaN in every output array, which
   * vtkRGBAErrorMetrics and hovr's measures leave out. For measuring large volumes and images,
   * where every pixel would take too long. Initial value is 1 (every pixel).
   */
  vtkSetClampMacro(PixelFraction, double, 0.0, 1.0);
  vtkGetMacro(PixelFraction, double);
  ///@}

  ///@{
  /**
   * Seed of the pixel sample (PixelFraction). Initial value is 1.
   */
  vtkSetMacro(PixelSeed, int);
  vtkGetMacro(PixelSeed, int);
  ///@}

  /**
   * Number of integration pieces (composite) or cells (other blend modes) evaluated by the
   * last update: the samples per frame.
   */
  vtkGetMacro(NumberOfSamples, vtkIdType);

#ifndef __VTK_WRAP__
  /**
   * What IntegrateRays() keeps of each ray from one call to the next (see there): per ray,
   * one byte per cell crossed before the ray stopped (1 where the cell meets opacity), and
   * the values of those cells in order: transmittance, then ColorNodes weights (ColorNodes
   * > 0) or RGB.
   */
  struct RayCells
  {
    int ColorNodes = 0;
    std::vector<std::vector<float>> Values;
    std::vector<std::vector<unsigned char>> Kept;
  };

  /**
   * The composite integral along arbitrary rays, for estimates that need the ground truth
   * off a camera's pixels (vtkPreIntegrationTableSizer). Ray r is o + t v, o = origins[3 r],
   * v = directions[3 r], in the 0-based continuous grid index of a volume whose points hold
   * values (x fastest, dims points), t the world distance along it (v is the index-space
   * image of a unit world direction), from t = 0 through the box of the points; rgba[4 r]
   * gets its premultiplied RGBA. As in an update, integration pieces change the scalar by at
   * most scalarTolerance times the narrowest feature the piece's values meet (features wider
   * than dataRange count as that wide); rays stop when their transmittance falls below
   * cutoff. The sampler must be prepared. Multithreaded with vtkSMPTools, or with lowPriority
   * in threads of low priority (vtkLowPriorityThreads). When abort is given and becomes
   * true, the rays not yet begun are left out (their rgba is not written).
   *
   * With cells (one entry per ray in its Values and Kept), the rays are composited cell by
   * cell from each cell's own values (transmittance and colour from its entry, in float), and
   * the values are kept there for the next call on the same rays and volume: a cell crossed
   * before keeps its values unless its reach (its corner range widened by its profile's sweep,
   * all its integration reads) meets [changed[0], changed[1]] (every cell is integrated again
   * without changed; none with an empty range). With ColorNodes > 0 a cell's colour is kept
   * as weights of that many colour nodes (vtkVolumeTransferFunctionSampler::GetColorWeights;
   * the colours must interpolate linearly) and composited from the nodes' present colours,
   * so that a colour edit (vtkVolumeTransferFunctionSampler::IsColorEditOf) integrates
   * nothing. A call aborted part way leaves the rays not yet begun with the old values: the
   * caller then drops them.
   */
  static void IntegrateRays(const vtkVolumeScalarView& values,
    const int dims[3],
    const vtkVolumeTransferFunctionSampler* sampler,
    double scalarTolerance,
    double dataRange,
    double cutoff,
    vtkIdType count,
    const double* origins,
    const double* directions,
    double* rgba,
    const std::atomic<bool>* abort = nullptr,
    bool lowPriority = false,
    RayCells* cells = nullptr,
    const double* changed = nullptr);
#endif

protected:
  vtkVolumeReferenceIntegrator();
  ~vtkVolumeReferenceIntegrator() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int BlendMode = COMPOSITE_BLEND;
  double ScalarTolerance = 1.0 / 64.0;
  double TransmittanceCutoff = 1e-7;
  double IsoPerturbation = 1e-6;
  double PixelFraction = 1.0;
  int PixelSeed = 1;
  vtkIdType NumberOfSamples = 0;
  vtkVolumeShadingModel* ShadingModel = nullptr;
  char* NormalArrayName = nullptr;

private:
  vtkVolumeReferenceIntegrator(const vtkVolumeReferenceIntegrator&) = delete;
  void operator=(const vtkVolumeReferenceIntegrator&) = delete;
};

#endif
