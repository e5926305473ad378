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
 */
#ifndef vtkPreIntegrationRayCaster_h
#define vtkPreIntegrationRayCaster_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkVolumeImageAlgorithm.h"

class vtkPreIntegrationTable;

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
   * only used for its order). Initial value is false.
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

private:
  vtkPreIntegrationRayCaster(const vtkPreIntegrationRayCaster&) = delete;
  void operator=(const vtkPreIntegrationRayCaster&) = delete;
};

#endif
