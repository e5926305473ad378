// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkFloatRGBARenderCapture
 * @brief   makes a render window draw into 32-bit float colour and reads it back as RGBA
 *
 * Measuring errors of order 1e-3 needs more than the 8 bits per channel of a window. Attach()
 * replaces the colour attachment of the window's offscreen render framebuffer by a 32-bit
 * float texture; VTK then renders exactly as usual (same passes, same depth handling) into
 * it, and Capture() reads it back into a vtkImageData whose point data "RGBA" (float, 4
 * components) holds what was drawn. With a transparent black background
 * (SetBackground(0, 0, 0), SetBackgroundAlpha(0)) and blending, volume mappers leave
 * premultiplied colour and alpha = 1 - transmittance, the layout of
 * vtkVolumeReferenceIntegrator's output. Pixel (i, j) is counted from left and bottom.
 *
 * The window must not multisample (SetMultiSamples(0)): a multisampled framebuffer has no
 * texture to replace, and sample coverage at the volume's edges would blend pixels anyway.
 */
#ifndef vtkFloatRGBARenderCapture_h
#define vtkFloatRGBARenderCapture_h

#include "hovrRenderingOpenGLModule.h" // For export macro
#include "vtkObject.h"

class vtkImageData;
class vtkRenderWindow;

class HOVRRENDERINGOPENGL_EXPORT vtkFloatRGBARenderCapture : public vtkObject
{
public:
  static vtkFloatRGBARenderCapture* New();
  vtkTypeMacro(vtkFloatRGBARenderCapture, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Give the window a float colour buffer. Renders the window once if its framebuffers do not
   * exist yet. Returns false and reports an error for a window that is not an OpenGL window
   * or that multisamples.
   */
  bool Attach(vtkRenderWindow* window);

  /**
   * Read the float colour buffer of the last render into image. Returns false and reports an
   * error when the window was not attached or its framebuffer was recreated since.
   */
  bool Capture(vtkImageData* image);

protected:
  vtkFloatRGBARenderCapture();
  ~vtkFloatRGBARenderCapture() override;

  vtkRenderWindow* Window = nullptr; // not referenced: the caller owns the window

private:
  vtkFloatRGBARenderCapture(const vtkFloatRGBARenderCapture&) = delete;
  void operator=(const vtkFloatRGBARenderCapture&) = delete;
};

#endif
