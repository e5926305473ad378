// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkObjectOrderVolumeMapper.h"

#include "vtkCamera.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkErrorForwarder.h"
#include "vtkFixedPointVolumeRayCastMapper.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkObjectFactory.h"
#include "vtkObjectOrderRayCaster.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkPointData.h"
#include "vtkRenderer.h"
#include "vtkTextureObject.h"
#include "vtkVolume.h"
#include "vtkVolumeImageAlgorithm.h"
#include "vtk_glew.h"

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkObjectOrderVolumeMapper);

//------------------------------------------------------------------------------
vtkObjectOrderVolumeMapper::vtkObjectOrderVolumeMapper()
  : Caster(vtkObjectOrderRayCaster::New())
  , Texture(vtkTextureObject::New())
  , Fallback(vtkFixedPointVolumeRayCastMapper::New())
  , FallbackPiece(vtkImageData::New())
{
  vtkErrorForwarder::Forward(this->Caster, this);
  this->Fallback->SetAutoAdjustSampleDistances(0);
  this->Fallback->SetLockSampleDistanceToInputSpacing(0);
}

//------------------------------------------------------------------------------
vtkObjectOrderVolumeMapper::~vtkObjectOrderVolumeMapper()
{
  this->Caster->Delete();
  this->Texture->Delete();
  this->Fallback->Delete();
  this->FallbackPiece->Delete();
}

//------------------------------------------------------------------------------
const char* vtkObjectOrderVolumeMapper::GetFallbackReason(vtkRenderer* ren, vtkVolume*)
{
  if (!ren->GetActiveCamera()->GetParallelProjection())
  {
    return "object-order ray casting needs a parallel projection";
  }
  if (this->BlendMode != vtkVolumeMapper::COMPOSITE_BLEND)
  {
    return "object-order ray casting does composite blending only";
  }
  if (this->Cropping)
  {
    return "object-order ray casting does not crop";
  }
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInputDataObject(0, 0));
  vtkDataArray* scalars = input ? this->GetRenderedArray(input) : nullptr;
  if (scalars && scalars->GetNumberOfComponents() != 1)
  {
    return "object-order ray casting renders single-component point scalars";
  }
  if (scalars && scalars == this->OutOfMemoryScalars &&
    scalars->GetMTime() == this->OutOfMemoryTime)
  {
    return "there is not enough memory for object-order ray casting's copy of the volume";
  }
  return nullptr;
}

//------------------------------------------------------------------------------
void vtkObjectOrderVolumeMapper::RenderFallback(vtkRenderer* ren,
  vtkVolume* vol,
  vtkImageData* input,
  const char* reason)
{
  if (this->LastWarning != reason)
  {
    vtkWarningMacro(<< reason << "; drawing with vtkFixedPointVolumeRayCastMapper.");
    this->LastWarning = reason;
  }
  this->LastFrameFellBack = true;
  const int* owned = this->Caster->GetOwnedExtent();
  if (owned[0] <= owned[1] && owned[2] <= owned[3] && owned[4] <= owned[5])
  {
    // A piece with ghost points: VTK's mapper draws the owned points alone, as the pieces of
    // the other ranks do theirs (a copy per frame, small beside that mapper's frame).
    this->FallbackPiece->ShallowCopy(input);
    this->FallbackPiece->Crop(owned);
    input = this->FallbackPiece;
  }
  this->Fallback->SetInputData(input);
  this->Fallback->SetBlendMode(this->BlendMode);
  this->Fallback->SetCropping(this->Cropping);
  this->Fallback->SetCroppingRegionPlanes(this->CroppingRegionPlanes);
  this->Fallback->SetCroppingRegionFlags(this->CroppingRegionFlags);
  this->Fallback->SetSampleDistance(this->SampleDistance);
  this->Fallback->SetScalarMode(this->ScalarMode);
  if (this->ArrayAccessMode == VTK_GET_ARRAY_BY_ID)
  {
    this->Fallback->SelectScalarArray(this->ArrayId);
  }
  else
  {
    this->Fallback->SelectScalarArray(this->ArrayName);
  }
  this->Fallback->Render(ren, vol);
}

//------------------------------------------------------------------------------
vtkDataArray* vtkObjectOrderVolumeMapper::GetRenderedArray(vtkImageData* input)
{
  // The mapper's scalar mode and array selection, as VTK's mappers read them.
  vtkPointData* points = input->GetPointData();
  switch (this->ScalarMode)
  {
    case VTK_SCALAR_MODE_DEFAULT:
    case VTK_SCALAR_MODE_USE_POINT_DATA:
      return points->GetScalars();
    case VTK_SCALAR_MODE_USE_POINT_FIELD_DATA:
      return this->ArrayAccessMode == VTK_GET_ARRAY_BY_ID ? points->GetArray(this->ArrayId)
                                                          : points->GetArray(this->ArrayName);
    default:
      return nullptr; // cell data
  }
}

//------------------------------------------------------------------------------
void vtkObjectOrderVolumeMapper::Render(vtkRenderer* ren, vtkVolume* vol)
{
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInputDataObject(0, 0));
  if (!input)
  {
    vtkErrorMacro("No input image to render.");
    return;
  }
  if (!this->GetRenderedArray(input))
  {
    // Neither this mapper nor vtkFixedPointVolumeRayCastMapper (which crashes on them) draws
    // cell scalars: an error, nothing drawn.
    vtkErrorMacro("Object-order ray casting renders point scalars; the scalar mode and array "
                  "selection choose no point array (cell data?). Nothing is drawn.");
    this->LastFrameFellBack = false;
    return;
  }
  if (const char* reason = this->GetFallbackReason(ren, vol))
  {
    this->RenderFallback(ren, vol, input, reason);
    return;
  }
  this->LastWarning.clear();
  this->LastFrameFellBack = false;

  int size[2], origin[2];
  ren->GetTiledSizeAndOrigin(&size[0], &size[1], &origin[0], &origin[1]);
  if (size[0] < 1 || size[1] < 1)
  {
    return;
  }
  this->InvokeEvent(vtkCommand::VolumeMapperRenderStartEvent, nullptr);
  this->Caster->SetInputData(input);
  vtkDataArray* scalars = this->GetRenderedArray(input);
  if (scalars && scalars != input->GetPointData()->GetScalars() && scalars->GetName())
  {
    this->Caster->SetInputArrayToProcess(
      0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, scalars->GetName());
  }
  else
  {
    this->Caster->SetInputArrayToProcess(
      0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
  }
  this->Caster->SetVolumeProperty(vol->GetProperty());
  this->Caster->SetVolumeMatrix(vol->GetMatrix());
  this->Caster->SetCamera(ren->GetActiveCamera());
  this->Caster->SetImageSize(size);
  this->Caster->SetSampleDistance(this->SampleDistance);
  this->Caster->Update();
  if (this->Caster->GetLastUpdateOutOfMemory())
  {
    // Remembered for these scalars, so that later frames do not try the allocation again.
    this->OutOfMemoryScalars = scalars;
    this->OutOfMemoryTime = scalars->GetMTime();
    this->InvokeEvent(vtkCommand::VolumeMapperRenderEndEvent, nullptr);
    this->RenderFallback(ren, vol, input, this->GetFallbackReason(ren, vol));
    return;
  }
  this->DrawImage(ren, size);
  this->InvokeEvent(vtkCommand::VolumeMapperRenderEndEvent, nullptr);
}

//------------------------------------------------------------------------------
void vtkObjectOrderVolumeMapper::DrawImage(vtkRenderer* ren, const int size[2])
{
  vtkFloatArray* rgba =
    vtkFloatArray::SafeDownCast(this->Caster->GetOutput()->GetPointData()->GetScalars());
  const vtkIdType n = static_cast<vtkIdType>(size[0]) * size[1];
  if (!rgba || rgba->GetNumberOfTuples() != n)
  {
    return; // the caster reported why
  }
  // Only the pixels that rays through the volume can reach: the image is zero elsewhere,
  // which "over" leaves unchanged, so uploading and drawing it would cost time for nothing.
  int pixels[4];
  this->Caster->GetLastVolumePixels(pixels);
  if (pixels[1] < pixels[0] || pixels[3] < pixels[2])
  {
    return; // the volume is out of view
  }
  // The float image, texel for pixel (nearest), composited over what is drawn: premultiplied
  // colour, so "over" is (1, 1 - alpha).
  vtkOpenGLRenderWindow* context = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!context)
  {
    vtkErrorMacro("Object-order ray casting draws its image with OpenGL; the render window "
                  "is not an OpenGL one.");
    return;
  }
  const int width = pixels[1] - pixels[0] + 1, height = pixels[3] - pixels[2] + 1;
  this->Texture->SetContext(context);
  this->Texture->SetInternalFormat(GL_RGBA32F);
  this->Texture->SetFormat(GL_RGBA);
  this->Texture->SetDataType(GL_FLOAT);
  // The rectangle's rows lie size[0] pixels apart in the image.
  glPixelStorei(GL_UNPACK_ROW_LENGTH, size[0]);
  const bool uploaded = this->Texture->Create2DFromRaw(width,
    height,
    4,
    VTK_FLOAT,
    rgba->GetPointer(4 * (pixels[0] + static_cast<vtkIdType>(size[0]) * pixels[2])));
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  if (!uploaded)
  {
    vtkErrorMacro("Could not upload the " << width << " x " << height << " image.");
    return;
  }
  this->Texture->SetMinificationFilter(vtkTextureObject::Nearest);
  this->Texture->SetMagnificationFilter(vtkTextureObject::Nearest);
  vtkOpenGLState* state = context->GetState();
  vtkOpenGLState::ScopedglBlendFuncSeparate blendSaver(state);
  vtkOpenGLState::ScopedglEnableDisable blendEnabled(state, GL_BLEND);
  vtkOpenGLState::ScopedglEnableDisable depthTest(state, GL_DEPTH_TEST);
  vtkOpenGLState::ScopedglDepthMask depthMask(state);
  state->vtkglEnable(GL_BLEND);
  state->vtkglBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  state->vtkglDisable(GL_DEPTH_TEST);
  state->vtkglDepthMask(GL_FALSE);
  this->Texture->Activate();
  this->Texture->CopyToFrameBuffer(0,
    0,
    width - 1,
    height - 1,
    pixels[0],
    pixels[2],
    pixels[1],
    pixels[3],
    size[0],
    size[1],
    nullptr,
    nullptr);
  this->Texture->Deactivate();
}

//------------------------------------------------------------------------------
void vtkObjectOrderVolumeMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  this->Texture->ReleaseGraphicsResources(window);
  this->Fallback->ReleaseGraphicsResources(window);
  this->Superclass::ReleaseGraphicsResources(window);
}

//------------------------------------------------------------------------------
void vtkObjectOrderVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "LastFrameFellBack: " << this->LastFrameFellBack << "\n";
  os << indent << "Caster:\n";
  this->Caster->PrintSelf(os, indent.GetNextIndent());
}

//------------------------------------------------------------------------------
double* vtkObjectOrderVolumeMapper::GetBounds()
{
  double* bounds = this->Superclass::GetBounds();
  vtkVolumeImageAlgorithm::ReportGeometry(
    this, vtkImageData::SafeDownCast(this->GetDataSetInput()), this->ReportedBoundsTime);
  return bounds;
}
