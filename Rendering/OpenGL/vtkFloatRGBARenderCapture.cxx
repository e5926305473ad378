// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkFloatRGBARenderCapture.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkPointData.h"
#include "vtkTextureObject.h"
#include "vtk_glew.h"

vtkStandardNewMacro(vtkFloatRGBARenderCapture);

namespace
{
bool HasFloatColor(vtkOpenGLFramebufferObject* fbo)
{
  vtkTextureObject* color = fbo ? fbo->GetColorAttachmentAsTextureObject(0) : nullptr;
  return color && color->GetVTKDataType() == VTK_FLOAT;
}
}

//------------------------------------------------------------------------------
vtkFloatRGBARenderCapture::vtkFloatRGBARenderCapture() = default;

//------------------------------------------------------------------------------
vtkFloatRGBARenderCapture::~vtkFloatRGBARenderCapture() = default;

//------------------------------------------------------------------------------
bool vtkFloatRGBARenderCapture::Attach(vtkRenderWindow* window)
{
  this->Window = nullptr;
  auto* glWindow = vtkOpenGLRenderWindow::SafeDownCast(window);
  if (!glWindow)
  {
    vtkErrorMacro("A float colour buffer needs an OpenGL render window.");
    return false;
  }
  if (glWindow->GetMultiSamples() > 0)
  {
    vtkErrorMacro("The render window multisamples (" << glWindow->GetMultiSamples()
                                                     << " samples); call SetMultiSamples(0).");
    return false;
  }
  vtkOpenGLFramebufferObject* fbo = glWindow->GetRenderFramebuffer();
  if (!fbo || fbo->GetFBOIndex() == 0)
  {
    glWindow->Render(); // framebuffers are created on the first render
    fbo = glWindow->GetRenderFramebuffer();
  }
  if (!fbo || !fbo->GetColorAttachmentAsTextureObject(0))
  {
    vtkErrorMacro("The render window has no offscreen colour texture to replace.");
    return false;
  }
  if (!HasFloatColor(fbo))
  {
    glWindow->MakeCurrent();
    const int* size = fbo->GetLastSize();
    vtkNew<vtkTextureObject> color;
    color->SetContext(glWindow);
    color->SetInternalFormat(GL_RGBA32F);
    color->SetFormat(GL_RGBA);
    color->SetDataType(GL_FLOAT);
    color->SetMinificationFilter(vtkTextureObject::Nearest);
    color->SetMagnificationFilter(vtkTextureObject::Nearest);
    color->Allocate2D(size[0], size[1], 4, VTK_FLOAT);
    vtkOpenGLState* state = glWindow->GetState();
    state->PushFramebufferBindings();
    fbo->Bind();
    fbo->AddColorAttachment(0, color);
    fbo->ActivateDrawBuffer(0);
    const bool complete = fbo->CheckFrameBufferStatus(GL_FRAMEBUFFER) != 0;
    state->PopFramebufferBindings();
    if (!complete)
    {
      vtkErrorMacro("The float colour buffer is not supported by this OpenGL implementation.");
      return false;
    }
  }
  this->Window = window;
  return true;
}

//------------------------------------------------------------------------------
bool vtkFloatRGBARenderCapture::Capture(vtkImageData* image)
{
  auto* glWindow = vtkOpenGLRenderWindow::SafeDownCast(this->Window);
  vtkOpenGLFramebufferObject* fbo = glWindow ? glWindow->GetRenderFramebuffer() : nullptr;
  if (!image || !HasFloatColor(fbo))
  {
    vtkErrorMacro("No float colour buffer: call Attach() after creating or resizing the window.");
    return false;
  }
  glWindow->MakeCurrent();
  const int* size = fbo->GetLastSize();
  vtkNew<vtkFloatArray> rgba;
  rgba->SetName("RGBA");
  rgba->SetNumberOfComponents(4);
  rgba->SetNumberOfTuples(static_cast<vtkIdType>(size[0]) * size[1]);
  vtkOpenGLState* state = glWindow->GetState();
  state->PushReadFramebufferBinding();
  fbo->Bind(GL_READ_FRAMEBUFFER);
  fbo->ActivateReadBuffer(0);
  state->vtkglPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, size[0], size[1], GL_RGBA, GL_FLOAT, rgba->GetPointer(0));
  state->PopReadFramebufferBinding();
  image->Initialize();
  image->SetExtent(0, size[0] - 1, 0, size[1] - 1, 0, 0);
  image->GetPointData()->SetScalars(rgba);
  return true;
}

//------------------------------------------------------------------------------
void vtkFloatRGBARenderCapture::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Window: " << this->Window << "\n";
}
