// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkFloatRGBARenderCapture.h"

#include "vtkFloatArray.h"
#include "vtkFramebufferPass.h"
#include "vtkImageData.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkPixelBufferObject.h"
#include "vtkPointData.h"
#include "vtkRenderStepsPass.h"
#include "vtkRenderer.h"
#include "vtkTextureObject.h"

vtkStandardNewMacro(vtkFloatRGBARenderCapture);

//------------------------------------------------------------------------------
vtkFloatRGBARenderCapture::vtkFloatRGBARenderCapture()
  : Pass(vtkFramebufferPass::New())
{
  vtkNew<vtkRenderStepsPass> steps;
  this->Pass->SetDelegatePass(steps);
  this->Pass->SetColorFormat(vtkTextureObject::Float32);
}

//------------------------------------------------------------------------------
vtkFloatRGBARenderCapture::~vtkFloatRGBARenderCapture()
{
  this->Pass->Delete();
}

//------------------------------------------------------------------------------
void vtkFloatRGBARenderCapture::Attach(vtkRenderer* renderer)
{
  this->Renderer = renderer;
  if (renderer)
  {
    renderer->SetPass(this->Pass);
  }
}

//------------------------------------------------------------------------------
bool vtkFloatRGBARenderCapture::Capture(vtkImageData* image)
{
  vtkTextureObject* color = this->Pass->GetColorTexture();
  if (!this->Renderer || !color || color->GetHandle() == 0 || !image)
  {
    vtkErrorMacro("Nothing was rendered through the float framebuffer yet.");
    return false;
  }
  if (vtkRenderWindow* window = this->Renderer->GetRenderWindow())
  {
    window->MakeCurrent();
  }
  const unsigned int w = color->GetWidth();
  const unsigned int h = color->GetHeight();
  vtkPixelBufferObject* pbo = color->Download();
  vtkNew<vtkFloatArray> rgba;
  rgba->SetName("RGBA");
  rgba->SetNumberOfComponents(4);
  rgba->SetNumberOfTuples(static_cast<vtkIdType>(w) * h);
  unsigned int dims[2] = { w, h };
  vtkIdType increments[2] = { 0, 0 };
  const bool ok = pbo && pbo->Download2D(VTK_FLOAT, rgba->GetPointer(0), dims, 4, increments);
  if (pbo)
  {
    pbo->Delete();
  }
  if (!ok)
  {
    vtkErrorMacro("Could not download the float colour buffer.");
    return false;
  }
  image->Initialize();
  image->SetExtent(0, static_cast<int>(w) - 1, 0, static_cast<int>(h) - 1, 0, 0);
  image->GetPointData()->SetScalars(rgba);
  return true;
}

//------------------------------------------------------------------------------
void vtkFloatRGBARenderCapture::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Renderer: " << this->Renderer << "\n";
}
