// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkPreIntegrationRayCaster
 * @brief   the CPU twin of vtkPreIntegrationVolumeMapper's compositing
 *
 * Casts the camera's pixel rays (vtkCameraRayModel) through the trilinear field and composites
 * them as the pre-integration GLSL does (hovrPreIntegration1.glsl, hovrPreIntegration2.glsl):
 * samples one SampleDistance apart from the point where the ray enters the box of the
 * volume's points, the first one a full step inside; first order composites each segment
 * between consecutive samples (and the partial last one up to the box exit) from the 2D table,
 * second order each slab of two sample distances (front, middle, back) from the 3D table and
 * what remains as a shorter slab through its front, midpoint and end; a partial segment or slab
 * keeps the table's colour per opacity and scales its optical depth by its length; a ray stops
 * once its opacity exceeds OpacityThreshold. Table lookups interpolate the entries as a GPU's
 * linear texture filtering does (entries at texel centres, clamped to the edge), in double.
 *
 * Everything is computed in double precision, so its error against
 * vtkVolumeReferenceIntegrator on the same camera is the method's (sampling, the segment
 * model, the table) without the GPU's float rounding. With ExactSegments, each segment or
 * slab is integrated through its model scalar path (linear or quadratic) directly instead of
 * read from the table: the error left is the segment model's alone, and the difference
 * between the two is the table's. That decomposition, on a small image, is what table sizes
 * are chosen and tested with.
 *
 * The table is the caller's (SetTable): a vtkFirstOrderPreIntegrationTable (front, back) or a
 * vtkSecondOrderPreIntegrationTable (chord centre, chord, deviation; with DeviationSize 1 a
 * first-order table over chords, as vtkPreIntegrationVolumeMapper uses for first order), whose
 * settings (sizes, ranges, prefilter, iterations) are the caller's; the caster sets their transfer
 * functions, segment length and scalar range (the data's finite range, as the mapper does) and
 * updates them. Point scalars, one component; NaN samples make their segments transparent, as on
 * the GPU.
 *
 * Shading (SetShadingModel), as vtkPreIntegrationVolumeMapper shades (Guetat
 * et al. 2010, hovrPreIntegrationShading.glsl): each segment takes the normals at its two ends
 * (its samples; the box entry for the first segment, the exit for the last): the gradient as
 * GradientOperator says (by default the reference integrator's, which the mapper uses) or the
 * trilinear interpolation of NormalArrayName's vectors, normalised (zero where it vanishes);
 * the view is the pixel ray's direction reversed; all in world coordinates, where the model's
 * lights are given (a headlight shines along the view). The segment is then composited:
 *   - from the table (ExactSegments off): the moment layers of a first-order
 *     vtkSecondOrderPreIntegrationTable (DeviationSize 1, Moments > 0: 2 layers for constant
 *     and linear gradient interpolation, 4 for non-linear), each read
 *     with the bilinear lookup of the unshaded path, lit by
 *     vtkVolumeShadingModel::ShadeSegment() with the model's GradientInterpolation; opacity
 *     J'_0 + J'_1; a partial segment scaled as an unshaded one. This is the CPU mirror of the
 *     GLSL: its image is the mapper's up to the GPU's float rounding;
 *   - exactly (ExactSegments on; the segment-model reference): the scalar linear across the
 * segment, the normal nlerp(front, back, u) normalised exactly (zero where it vanishes),
 * ShadedSubsteps midpoint steps per segment (more where the transfer function needs finer ones, as
 * the unshaded exact path takes them), each lit by vtkVolumeShadingModel::ShadePoint() (with the
 * model's SpecularModel: CONE is what the table path uses) times the step's opacity 1 - exp(-tau
 * dt), composited front to back in double. With the cone, the mapper's error against R2 is that of
 * shaded pre-integration's approximations (the quadratic normalisation of Eq. 5, the fades of the
 * cases, the tables), and R2's error against vtkVolumeReferenceIntegrator with the same model that
 * of the segment model (linear scalar, nlerp normal).
 *
 * Shaded second order takes the normals at each slab's front, middle and back (for the last,
 * shorter slab: its front, midpoint and end) and composites the slab
 *   - from the table: the slab moment layers of a vtkSecondOrderPreIntegrationTable
 *     (SlabMoments as many as first order's Moments: 2 or 4) read with the trilinear lookup,
 *     each half slab lit by ShadeSegment() between its end normals, the two summed, as
 *     hovrPreIntegration2.glsl does;
 *   - exactly (R2 of the slab model): the scalar on the quadratic (Eq. 2), the normal nlerp
 *     over each half, point by point as for first order.
 * The table path with a table without the moment layers the interpolation reads is an error
 * (an empty image). The model is used as given, whatever the
 * property's Shade flag: its coefficients and lights are the caller's
 * (vtkVolumeShadingModel::SetFromProperty copies the property's coefficients).
 */
#ifndef vtkPreIntegrationRayCaster_h
#define vtkPreIntegrationRayCaster_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkVolumeImageAlgorithm.h"

class vtkPreIntegrationTable;
class vtkVolumeShadingModel;

class HOVRRENDERINGCORE_EXPORT vtkPreIntegrationRayCaster : public vtkVolumeImageAlgorithm
{
public:
  static vtkPreIntegrationRayCaster* New();
  vtkTypeMacro(vtkPreIntegrationRayCaster, vtkVolumeImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Distance between samples along a ray in world units; must be positive. Initial value is 1.
   */
  vtkSetMacro(SampleDistance, double);
  vtkGetMacro(SampleDistance, double);
  ///@}

  ///@{
  /**
   * The pre-integration table: its dimension chooses the order (2: first, 3: second).
   * Initial value is nullptr (an error on update).
   */
  virtual void SetTable(vtkPreIntegrationTable*);
  vtkGetObjectMacro(Table, vtkPreIntegrationTable);
  ///@}

  enum Integrations
  {
    TABLE_ORDER = 0, ///< first order for vtkFirstOrderPreIntegrationTable, else second
    FIRST_ORDER = 1, ///< segments between samples (a vtkSecondOrderPreIntegrationTable must
                     ///< then have DeviationSize 1: a first-order table over chords)
    SECOND_ORDER = 2 ///< slabs of two sample distances (vtkSecondOrderPreIntegrationTable)
  };

  ///@{
  /**
   * How samples are composited. Initial value is TABLE_ORDER.
   */
  vtkSetClampMacro(Integration, int, TABLE_ORDER, SECOND_ORDER);
  vtkGetMacro(Integration, int);
  ///@}

  ///@{
  /**
   * Integrate each segment's model scalar path instead of reading the table (which is then
   * only used for its order); shaded, the segment-model reference R2 (see the class
   * description). Initial value is false.
   */
  vtkSetMacro(ExactSegments, bool);
  vtkGetMacro(ExactSegments, bool);
  vtkBooleanMacro(ExactSegments, bool);
  ///@}

  ///@{
  /**
   * A ray stops once its opacity exceeds this value. Initial value is the mapper's, 1 - 1/255.
   */
  vtkSetClampMacro(OpacityThreshold, double, 0.0, 1.0);
  vtkGetMacro(OpacityThreshold, double);
  ///@}

  ///@{
  /**
   * The most samples a ray may take across the volume's diagonal at the sample distance; a
   * finer sample distance is an error (empty image) instead of a frame of hours. Initial value
   * is 100000, as vtkPreIntegrationVolumeMapper's.
   */
  vtkSetClampMacro(MaximumSamplesPerRay, double, 1.0, 1e9);
  vtkGetMacro(MaximumSamplesPerRay, double);
  ///@}

  ///@{
  /**
   * The lighting of shaded compositing (see the class description): nullptr
   * composites unshaded. Initial value is nullptr.
   */
  virtual void SetShadingModel(vtkVolumeShadingModel*);
  vtkGetObjectMacro(ShadingModel, vtkVolumeShadingModel);
  ///@}

  ///@{
  /**
   * Shading: the point array of 3-component vectors whose trilinear interpolation,
   * normalised, is the normal (as vtkPreIntegrationVolumeMapper::NormalArrayName and
   * vtkVolumeReferenceIntegrator::NormalArrayName), instead of the gradient; in world units
   * (the data's coordinates). nullptr or empty: the gradient. Initial value is nullptr.
   */
  vtkSetStringMacro(NormalArrayName);
  vtkGetStringMacro(NormalArrayName);
  ///@}

  enum GradientOperators
  {
    GPU_GRADIENTS = 0,  ///< VTK 9.1's stock GPU ray caster's (computeGradient)
    POINT_GRADIENTS = 1 ///< vtkVolumeReferenceIntegrator's and the mapper's
  };

  ///@{
  /**
   * Shading: the gradient that gives the normals (without NormalArrayName), divided by the
   * spacing. GPU_GRADIENTS: the difference of the trilinear field one texture cell step either
   * side along each axis, as VTK's shader takes it: the step is 1 / (n - 1) of a texture of n
   * texels, n / (n - 1) points (1.025 for 41 points), not one point; the positions clamped to
   * the box as the texture's clamp-to-edge does. POINT_GRADIENTS: the trilinear interpolation
   * of per-point differences of the neighbours one point away, one-sided at the faces
   * (vtkVolumeReferenceIntegrator's; the difference of the trilinear field one point either
   * side; vtkPreIntegrationVolumeMapper's, whose bricks would give VTK's a different reach in
   * each). Both are the central difference of the trilinear field, at slightly different
   * reaches: with POINT_GRADIENTS the table path draws the mapper's image and R2 differs from
   * the reference integrator by the segment model alone. Initial value is POINT_GRADIENTS.
   */
  vtkSetClampMacro(GradientOperator, int, GPU_GRADIENTS, POINT_GRADIENTS);
  vtkGetMacro(GradientOperator, int);
  ///@}

  ///@{
  /**
   * Shaded exact segments (R2): midpoint steps per segment, at least (more where the transfer
   * function's narrowest feature the segment meets needs them). Initial value is 256.
   */
  vtkSetClampMacro(ShadedSubsteps, int, 1, 1000000);
  vtkGetMacro(ShadedSubsteps, int);
  ///@}

  vtkMTimeType GetMTime() override;

protected:
  vtkPreIntegrationRayCaster();
  ~vtkPreIntegrationRayCaster() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double SampleDistance = 1.0;
  vtkPreIntegrationTable* Table = nullptr;
  bool ExactSegments = false;
  int Integration = TABLE_ORDER;
  double OpacityThreshold = 1.0 - 1.0 / 255.0;
  double MaximumSamplesPerRay = 1e5;
  vtkVolumeShadingModel* ShadingModel = nullptr;
  char* NormalArrayName = nullptr;
  int ShadedSubsteps = 256;
  int GradientOperator = POINT_GRADIENTS;

private:
  vtkPreIntegrationRayCaster(const vtkPreIntegrationRayCaster&) = delete;
  void operator=(const vtkPreIntegrationRayCaster&) = delete;
};

#endif
