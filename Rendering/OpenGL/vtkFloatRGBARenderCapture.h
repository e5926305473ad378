// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkFloatRGBARenderCapture
 * @brief   renders a renderer into a 32-bit float framebuffer and reads it back as RGBA
 *
 * Measuring errors of order 1e-3 needs more than the 8 bits per channel of a window: this
 * class installs a vtkFramebufferPass with a Float32 colour buffer on a renderer (its
 * delegate being VTK's usual vtkRenderStepsPass) and, after a render, downloads that buffer
 * into a vtkImageData whose point data "RGBA" (float, 4 components) holds what the renderer
 * drew. With a transparent black background (SetBackground(0,0,0), SetBackgroundAlpha(0))
 * volume mappers leave premultiplied colour and alpha = 1 - transmittance, the layout of
 * vtkVolumeReferenceIntegrator's output. Pixel (i, j) is counted from left and bottom.
 */
#ifndef vtkFloatRGBARenderCapture_h
#define vtkFloatRGBARenderCapture_h

#include "hovrRenderingOpenGLModule.h" // For export macro
#include "vtkObject.h"

class vtkFramebufferPass;
class vtkImageData;
class vtkRenderer;

class HOVRRENDERINGOPENGL_EXPORT vtkFloatRGBARenderCapture : public vtkObject
{
public:
  static vtkFloatRGBARenderCapture* New();
  vtkTypeMacro(vtkFloatRGBARenderCapture, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Install the float framebuffer pass on a renderer (replacing its pass).
   */
  void Attach(vtkRenderer* renderer);

  /**
   * Download the float colour buffer of the last render into image. Returns false and
   * reports an error when nothing was rendered through the pass yet.
   */
  bool Capture(vtkImageData* image);

protected:
  vtkFloatRGBARenderCapture();
  ~vtkFloatRGBARenderCapture() override;

  vtkFramebufferPass* Pass;
  vtkRenderer* Renderer = nullptr; // not referenced: the renderer owns the pass

private:
  vtkFloatRGBARenderCapture(const vtkFloatRGBARenderCapture&) = delete;
  void operator=(const vtkFloatRGBARenderCapture&) = delete;
};

#endif
