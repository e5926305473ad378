// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkObjectOrderVolumeMapper
 * @brief   CPU volume mapper: object-order ray casting (Mora, Jessel and Caubet)
 *
 * A vtkVolumeMapper for renderers without a GPU (pvbatch on cluster nodes, CI machines): each
 * frame, vtkObjectOrderRayCaster computes the image of the volume for the renderer's camera
 * and viewport on the CPU (min-max octree, hidden volume removal, threads through
 * vtkSMPTools, the same image for any number of threads), and the float image is drawn over
 * the viewport, one texel per pixel, composited over what is already there; only the
 * rectangle of pixels the volume can cover (vtkObjectOrderRayCaster::GetLastVolumePixels) is
 * uploaded and drawn.
 *
 * Composite blending of single-component point scalars (the array the scalar mode and
 * SelectScalarArray choose) in parallel projection. Anything else (a perspective camera,
 * another blend mode, cropping, several components) is drawn by an
 * internal vtkFixedPointVolumeRayCastMapper with the same sample distance, after a warning
 * given once per reason: never a wrong image. Cell scalars, which that mapper does not draw
 * either, are an error and nothing is drawn. Shading follows the volume property; the
 * caster's ShadingMode (GetCaster()) chooses post- or pre-shading.
 */
#ifndef vtkObjectOrderVolumeMapper_h
#define vtkObjectOrderVolumeMapper_h

#include "hovrRenderingOpenGLModule.h" // For export macro
#include "vtkVolumeMapper.h"

#include <string> // For std::string

class vtkDataArray;
class vtkFixedPointVolumeRayCastMapper;
class vtkImageData;
class vtkObjectOrderRayCaster;
class vtkTextureObject;

class HOVRRENDERINGOPENGL_EXPORT vtkObjectOrderVolumeMapper : public vtkVolumeMapper
{
public:
  static vtkObjectOrderVolumeMapper* New();
  vtkTypeMacro(vtkObjectOrderVolumeMapper, vtkVolumeMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Distance between samples along each ray, in world units; must be positive. Initial
   * value is 1.
   */
  vtkSetMacro(SampleDistance, double);
  vtkGetMacro(SampleDistance, double);
  ///@}

  /**
   * The object-order ray caster: its settings (InterleavedSampling, HiddenVolumeRemoval,
   * OpacityThreshold, TileSize) and the counters of the last frame.
   */
  vtkObjectOrderRayCaster* GetCaster() { return this->Caster; }

  /**
   * Whether the last frame was drawn by the internal vtkFixedPointVolumeRayCastMapper: for a
   * perspective camera, a blend mode other than composite, cropping, multi-component scalars,
   * or scalars for which the caster ran out of memory (see
   * vtkObjectOrderRayCaster::GetLastUpdateOutOfMemory; tried again when they change).
   */
  vtkGetMacro(LastFrameFellBack, bool);

  void Render(vtkRenderer* ren, vtkVolume* vol) override;

  /**
   * The input's bounds; an error when they are not finite (a NaN origin, an infinite
   * spacing), since the renderer then culls the volume and never asks for a frame.
   */
  double* GetBounds() VTK_SIZEHINT(6) override;
  using vtkAbstractMapper3D::GetBounds;
  void ReleaseGraphicsResources(vtkWindow* window) override;

protected:
  vtkObjectOrderVolumeMapper();
  ~vtkObjectOrderVolumeMapper() override;

  // The point array the scalar mode and array selection choose, or nullptr (cell data).
  vtkDataArray* GetRenderedArray(vtkImageData* input);

  // Why the caster cannot draw this frame, or nullptr.
  const char* GetFallbackReason(vtkRenderer* ren, vtkVolume* vol);

  // The frame drawn by vtkFixedPointVolumeRayCastMapper, with a warning when the reason is new.
  void RenderFallback(vtkRenderer* ren, vtkVolume* vol, vtkImageData* input, const char* reason);

  // The caster's image (of size[0] x size[1] pixels) over what the renderer has drawn.
  void DrawImage(vtkRenderer* ren, const int size[2]);

  double SampleDistance = 1.0;
  bool LastFrameFellBack = false;
  std::string LastWarning;
  // The scalars (and their modification time) the caster last ran out of memory for.
  vtkDataArray* OutOfMemoryScalars = nullptr; // not referenced: only compared
  vtkMTimeType OutOfMemoryTime = 0;
  vtkMTimeType ReportedBoundsTime = 0; // the input time whose bounds GetBounds reported
  vtkObjectOrderRayCaster* Caster;
  vtkTextureObject* Texture;
  vtkFixedPointVolumeRayCastMapper* Fallback;
  // The owned points of a piece with ghost points (the caster's OwnedExtent), for Fallback.
  vtkImageData* FallbackPiece;

private:
  vtkObjectOrderVolumeMapper(const vtkObjectOrderVolumeMapper&) = delete;
  void operator=(const vtkObjectOrderVolumeMapper&) = delete;
};

#endif
