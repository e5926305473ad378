// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkCameraRayModel
 * @brief   the ray of each pixel of a vtkCamera, as VTK's renderers cast it
 *
 * The one camera model of hovr: the reference integrator casts these rays, the GPU mappers get
 * the same rays from VTK's projection of the same vtkCamera, and the benchmark compares them
 * pixel by pixel. Pixel (i, j) is counted from the left and the bottom and its ray passes
 * through the pixel centre, x = 2 (i + 1/2) / W - 1 and y = 2 (j + 1/2) / H - 1:
 *   - parallel projection: origin = position + x s (W/H) right + y s up, direction = forward,
 *     s being the camera's parallel scale;
 *   - perspective: origin = position, direction = normalize(forward + x t (W/H) right + y t up),
 *     t = tan(view angle / 2) (VTK's view angle is vertical; with the camera's
 *     UseHorizontalViewAngle on it is horizontal and t = tan(view angle / 2) H/W).
 * forward = normalize(focal point - position), right = normalize(forward x view up),
 * up = right x forward. Window centre, shear and stereo are not modelled.
 */
#ifndef vtkCameraRayModel_h
#define vtkCameraRayModel_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkObject.h"

class vtkCamera;
class vtkDataArray;
class vtkDoubleArray;
class vtkImageData;
class vtkMatrix4x4;

class HOVRRENDERINGCORE_EXPORT vtkCameraRayModel : public vtkObject
{
public:
  static vtkCameraRayModel* New();
  vtkTypeMacro(vtkCameraRayModel, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The camera whose rays are cast. Initial value is nullptr.
   */
  virtual void SetCamera(vtkCamera*);
  vtkGetObjectMacro(Camera, vtkCamera);
  ///@}

  ///@{
  /**
   * Image size W x H in pixels. Initial value is 256 x 256.
   */
  vtkSetVector2Macro(ImageSize, int);
  vtkGetVector2Macro(ImageSize, int);
  ///@}

  /**
   * Compute the camera frame. Returns false and reports an error for a missing camera, an
   * image size below 1 pixel, a position equal to the focal point, a view up parallel to the
   * view direction, or a view angle or parallel scale that is not positive.
   */
  bool Prepare();

  /**
   * Ray of pixel (i, j): origin and unit direction in world coordinates. Requires Prepare().
   */
  void GetPixelRay(int i, int j, double origin[3], double direction[3]) const;

  /**
   * Ray through image coordinates (x, y) in [-1, 1]^2 (the pixel centre formula above).
   */
  void GetRay(double x, double y, double origin[3], double direction[3]) const;

  /**
   * Samples a fixed-step ray caster takes over the whole image: for each pixel ray, the
   * number of steps of length step that fit into its chord through the box of the volume's
   * points (no early termination). Requires Prepare(); returns -1 for a step that is not
   * positive.
   */
  vtkIdType CountFixedStepSamples(vtkImageData* volume, double step) const;

  /**
   * Cells of the volume's grid that the pixel rays cross, summed over the image (the cells an
   * analytic ray caster visits without early termination). Requires Prepare().
   */
  vtkIdType CountCellVisits(vtkImageData* volume) const;

  /**
   * Depth of surface hits given as grid positions: for each pixel, positions holds (i, j, k,
   * w) in 0-based continuous grid index of the volume; where w > 0, depth is the world
   * distance along the pixel's ray from its origin to the projection of that point onto the
   * ray, else NaN. positions has W x H tuples of 4 components; depth is resized to W x H.
   * Requires Prepare().
   */
  void ComputeDepths(vtkImageData* volume, vtkDataArray* positions, vtkDoubleArray* depth) const;

  /**
   * The pixel rays in the continuous grid index of a volume (0-based from its extent's first
   * point) drawn with the prop matrix propMatrix (nullptr: identity), as an affine frame that a
   * GPU can evaluate per pixel in float. The ray of pixel (i, j) passes through
   *   base(i, j) = centre + (i + 1/2 - W/2) dx + (j + 1/2 - H/2) dy,
   * a point on the plane through the volume's centre facing the camera, with direction
   * base(i, j) - eye (perspective) or forward (parallel; eye is then set to centre - forward).
   * Points near the volume keep float rounding at the scale of the volume instead of the
   * camera's distance. Directions are not normalised. Requires Prepare(); returns false for a
   * missing volume or a singular prop matrix.
   */
  bool GetGridRayFrame(vtkImageData* volume,
    vtkMatrix4x4* propMatrix,
    double centre[3],
    double dx[3],
    double dy[3],
    double eye[3],
    double forward[3],
    bool& perspective) const;
  /**
   * Largest distance, in normalised device coordinates, between the pixel centres and VTK's
   * own projection of points along their rays (vtkCamera::GetCompositeProjectionTransformMatrix
   * at the image's aspect), over the corner and centre pixels. Near 0 for cameras the model
   * describes; large for the ones it does not (window centre, view shear, stereo, explicit
   * projection or model transforms). Requires Prepare().
   */
  double ComputeProjectionMismatch() const;
  vtkMTimeType GetMTime() override;

protected:
  vtkCameraRayModel();
  ~vtkCameraRayModel() override;

  vtkCamera* Camera = nullptr;
  int ImageSize[2] = { 256, 256 };

  // Frame computed by Prepare().
  double Position[3] = { 0, 0, 0 };
  double Forward[3] = { 0, 0, -1 };
  double Right[3] = { 1, 0, 0 };
  double Up[3] = { 0, 1, 0 };
  double HalfWidth = 1.0;  // parallel: world units; perspective: tangent
  double HalfHeight = 1.0; // idem
  bool Parallel = false;

private:
  vtkCameraRayModel(const vtkCameraRayModel&) = delete;
  void operator=(const vtkCameraRayModel&) = delete;
};

#endif
