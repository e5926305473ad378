// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkExtensibleGPUVolumeRayCastMapper.h"

#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationObjectBaseVectorKey.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderPass.h"
#include "vtkOpenGLRenderTimer.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLVolumeBricks.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPreIntegrationTable.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtkVolume.h"
#include "vtkVolumeBrickLayout.h"
#include "vtkVolumeImageAlgorithm.h"
#include "vtkVolumeProperty.h"
#include "vtk_glew.h"

#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>
#include <string>

//------------------------------------------------------------------------------
// The hook: a render pass that is never rendered as a pass. The ray caster calls it while it
// builds its shader and on every draw (see the class documentation).
class vtkGPURayCastShaderHook : public vtkOpenGLRenderPass
{
public:
  static vtkGPURayCastShaderHook* New();
  vtkTypeMacro(vtkGPURayCastShaderHook, vtkOpenGLRenderPass);

  vtkExtensibleGPUVolumeRayCastMapper* Mapper = nullptr;

  void Render(const vtkRenderState*) override {}

  bool PreReplaceShaderValues(std::string& vertexShader,
    std::string&,
    std::string& fragmentShader,
    vtkAbstractMapper*,
    vtkProp* prop) override
  {
    return this->Mapper->ReplaceExtensionShaderValues(
      vertexShader, fragmentShader, vtkVolume::SafeDownCast(prop));
  }

  bool SetShaderParameters(vtkShaderProgram* program,
    vtkAbstractMapper*,
    vtkProp* prop,
    vtkOpenGLVertexArrayObject*) override
  {
    this->Mapper->SetExtensionShaderParameters(program, vtkVolume::SafeDownCast(prop));
    return true;
  }

  // After VTK's own replacements: the program as compiled, kept for inspection.
  bool PostReplaceShaderValues(std::string&,
    std::string&,
    std::string& fragmentShader,
    vtkAbstractMapper*,
    vtkProp*) override
  {
    this->Mapper->FragmentShaderSource = fragmentShader;
    return true;
  }

  vtkMTimeType GetShaderStageMTime() override { return this->Mapper->ExtensionShaderTime; }

protected:
  vtkGPURayCastShaderHook() { this->ActiveDrawBuffers = 1; }
  ~vtkGPURayCastShaderHook() override = default;
};
vtkStandardNewMacro(vtkGPURayCastShaderHook);

//------------------------------------------------------------------------------
vtkExtensibleGPUVolumeRayCastMapper::vtkExtensibleGPUVolumeRayCastMapper()
  : Hook(vtkGPURayCastShaderHook::New())
  , DrawTimer(new vtkOpenGLRenderTimer)
{
  this->Bricks = vtkOpenGLVolumeBricks::New();
  this->RayModel = vtkCameraRayModel::New();
  this->Proxy = vtkImageData::New();
  this->Hook->Mapper = this;
  this->AutoAdjustSampleDistances = 0;
  this->ExtensionShaderTime.Modified();
}

//------------------------------------------------------------------------------
vtkExtensibleGPUVolumeRayCastMapper::~vtkExtensibleGPUVolumeRayCastMapper()
{
  this->Hook->Mapper = nullptr;
  this->Hook->Delete();
  this->Bricks->Delete();
  this->RayModel->Delete();
  this->Proxy->Delete();
  this->SetTextureScalars(nullptr);
  this->WidenedTextureScalars(nullptr);
}

//------------------------------------------------------------------------------
bool vtkExtensibleGPUVolumeRayCastMapper::ReplaceShaderTag(std::string& source,
  const std::string& tag,
  const std::string& code,
  TagPlacement placement)
{
  // Inserted code must not carry tags: a later replacement would hit the copy, not the template.
  if (code.find("//VTK::") != std::string::npos)
  {
    return false;
  }
  const std::string replacement = placement == BeforeTag ? code + "\n" + tag
    : placement == AfterTag                              ? tag + "\n" + code
                                                         : code;
  return vtkShaderProgram::Substitute(source, tag, replacement, false);
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::GPURender(vtkRenderer* ren, vtkVolume* vol)
{
  this->BrickedThisFrame = false;
  const FramePlan plan = this->PrepareExtension(ren, vol);
  if (plan == DrawNothing)
  {
    return;
  }
  // Times the draw (whatever path returns) without waiting for the query: the time read is the
  // last completed one.
  struct TimedDraw
  {
    vtkExtensibleGPUVolumeRayCastMapper* Mapper;
    bool Timed;
    ~TimedDraw()
    {
      if (this->Timed)
      {
        this->Mapper->DrawTimer->ReusableStop();
        this->Mapper->LastDrawTime = this->Mapper->DrawTimer->GetReusableElapsedSeconds();
      }
    }
  } timed{ this, vtkOpenGLRenderTimer::IsSupported() };
  if (timed.Timed)
  {
    this->DrawTimer->ReusableStart();
  }
  // VTK draws nothing, with no error but log lines, from a volume texture it cannot create.
  // Bricked frames give VTK only a proxy of each brick's box.
  if (!(plan == DrawWithExtension && this->BrickedThisFrame) &&
    !this->CheckFrameVolumeTexture(ren, plan == DrawWithExtension ? this->TextureScalars : nullptr))
  {
    return;
  }
  this->PlaceTextureScalars(plan == DrawWithExtension ? this->TextureScalars : nullptr);
  if (plan == DrawStock)
  {
    this->DrawStockOwned(ren, vol);
    return;
  }

  // Attach the hook for this draw only, next to any pass already there (e.g. depth peeling).
  vtkInformation* keys = vol->GetPropertyKeys();
  if (!keys)
  {
    vtkNew<vtkInformation> info;
    vol->SetPropertyKeys(info);
    keys = info;
  }
  vtkInformationObjectBaseVectorKey* passes = vtkOpenGLRenderPass::RenderPasses();
  passes->Append(keys, this->Hook);

  if (this->BrickedThisFrame)
  {
    this->DrawBrickedFrame(ren, vol);
  }
  else
  {
    this->ActivateExtensionTextures();
    this->Superclass::GPURender(ren, vol);
    this->DeactivateExtensionTextures();
  }
  this->ExtensionFrameCount++;

  passes->Remove(keys, this->Hook);
  if (passes->Length(keys) == 0)
  {
    keys->Remove(passes);
  }
}

//------------------------------------------------------------------------------
bool vtkExtensibleGPUVolumeRayCastMapper::PrepareBricks(vtkRenderer* ren,
  vtkDataArray* scalars,
  const int dims[3],
  int ghostPoints,
  int precision,
  bool filtered,
  int minimumBytes,
  int maximumPoints,
  bool atlas)
{
  vtkOpenGLRenderWindow* context = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  const int largest = context ? vtkTextureObject::GetMaximumTextureSize3D(context) : 0;
  int points = largest > 0 ? largest : 2048;
  if (this->MaximumBrickSize > 0)
  {
    points = std::min(points, this->MaximumBrickSize);
  }
  if (maximumPoints > 0)
  {
    points = std::min(points, std::max(maximumPoints, 2 * ghostPoints + 2));
  }
  vtkVolumeBrickLayout* layout = this->Bricks->GetLayout();
  layout->SetGhostPoints(ghostPoints);
  layout->SetMaximumBrickPoints(points);
  layout->SetMaximumBrickBytes(static_cast<double>(this->MaximumTextureBytes));
  this->Bricks->SetPrecision(precision);
  this->Bricks->SetFiltered(filtered);
  this->Bricks->SetMinimumBytesPerPoint(minimumBytes);
  this->Bricks->SetAtlas(atlas);
  std::string why;
  if (!this->Bricks->Update(context, scalars, dims, why))
  {
    vtkErrorMacro("Cannot draw the volume: " << why << ". Not drawing.");
    return false;
  }
  this->BrickedThisFrame = true;
  return true;
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::GetBrickCells(int cells[6])
{
  this->Bricks->GetLayout()->GetBrickCells(this->CurrentBrick, cells);
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::GetBrickPoints(int points[6])
{
  this->Bricks->GetLayout()->GetBrickPoints(this->CurrentBrick, points);
}

//------------------------------------------------------------------------------
int vtkExtensibleGPUVolumeRayCastMapper::GetNumberOfBricks()
{
  return this->Bricks->GetNumberOfBricks();
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::GetBrickOrigin(int brick, int origin[3])
{
  int points[6];
  this->Bricks->GetLayout()->GetBrickPoints(brick, points);
  for (int a = 0; a < 3; ++a)
  {
    origin[a] = points[2 * a];
  }
}

//------------------------------------------------------------------------------
vtkIdType vtkExtensibleGPUVolumeRayCastMapper::GetBrickTextureMemorySize()
{
  return this->Bricks->GetMemorySize();
}

//------------------------------------------------------------------------------
int vtkExtensibleGPUVolumeRayCastMapper::GetNumberOfBrickTextures()
{
  return this->Bricks->GetNumberOfTextures();
}

//------------------------------------------------------------------------------
int vtkExtensibleGPUVolumeRayCastMapper::GetBrickUploadCount()
{
  return this->Bricks->GetUploadCount();
}

//------------------------------------------------------------------------------
int vtkExtensibleGPUVolumeRayCastMapper::GetBrickTextureCreateCount()
{
  return this->Bricks->GetCreateCount();
}

//------------------------------------------------------------------------------
vtkTextureObject* vtkExtensibleGPUVolumeRayCastMapper::GetBrickTexture()
{
  return this->Bricks->GetTexture(this->CurrentBrick);
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::DrawBrickedFrame(vtkRenderer* ren, vtkVolume* vol)
{
  this->DrawBrickRound(ren, vol);
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::DrawBrickRound(vtkRenderer* ren, vtkVolume* vol)
{
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  int cellFlag = 0;
  vtkDataArray* scalars = vtkAbstractMapper::GetScalars(
    input, this->ScalarMode, this->ArrayAccessMode, this->ArrayId, this->ArrayName, cellFlag);
  // VTK draws each brick's box from a 2 x 2 x 2 proxy of the scalars' type holding their
  // finite range, so that its transfer-function tables and texture mapping are the input's.
  if (!this->ProxyScalars || this->ProxyScalars->GetDataType() != scalars->GetDataType())
  {
    this->ProxyScalars.TakeReference(vtkDataArray::CreateDataArray(scalars->GetDataType()));
    this->ProxyScalars->SetNumberOfValues(8);
    this->Proxy->GetPointData()->SetScalars(this->ProxyScalars);
  }
  this->ProxyScalars->SetName(scalars->GetName());
  double range[2], tableRange[2];
  if (!vtkPreIntegrationTable::ComputeScalarRange(scalars, range, tableRange, this->ScalarRange))
  {
    scalars->GetFiniteRange(range, 0);
  }
  for (vtkIdType i = 0; i < 8; ++i)
  {
    this->ProxyScalars->SetComponent(i, 0, i < 4 ? range[0] : range[1]);
  }
  this->ProxyScalars->Modified();
  this->Proxy->SetDimensions(2, 2, 2);
  this->Proxy->SetDirectionMatrix(input->GetDirectionMatrix());

  // Back to front: the viewer in 0-based grid index (the eye, or the view direction).
  vtkCamera* camera = ren->GetActiveCamera();
  vtkNew<vtkMatrix4x4> toData;
  vtkMatrix4x4::Invert(vol->GetMatrix(), toData);
  const bool parallel = camera->GetParallelProjection() != 0;
  double eye[4] = { 0, 0, 0, 1 }, viewer[3];
  camera->GetPosition(eye);
  eye[3] = 1.0;
  double direction[4] = { 0, 0, 0, 0 };
  camera->GetDirectionOfProjection(direction);
  double* point = parallel ? direction : eye;
  toData->MultiplyPoint(point, point);
  const int* extent = input->GetExtent();
  if (parallel)
  {
    // Directions map through the linear part of physical -> index.
    double origin[3] = { 0, 0, 0 }, tip[3];
    input->TransformPhysicalPointToContinuousIndex(origin, origin);
    input->TransformPhysicalPointToContinuousIndex(point, tip);
    for (int a = 0; a < 3; ++a)
    {
      viewer[a] = tip[a] - origin[a];
    }
  }
  else
  {
    input->TransformPhysicalPointToContinuousIndex(point, viewer);
    for (int a = 0; a < 3; ++a)
    {
      viewer[a] -= extent[2 * a];
    }
  }
  vtkNew<vtkIdList> order;
  const bool atlas = this->Bricks->GetAtlas();
  if (atlas)
  {
    order->InsertNextId(0); // one box, the whole volume's, over the atlas
  }
  else
  {
    this->Bricks->GetLayout()->GetBackToFront(viewer, parallel, order);
  }

  // VTK's ray caster reads its input from the shallow copy it keeps; the proxy stands in for
  // it during the bricks' draws.
  vtkDataSet*& slot = this->TransformedInputs[0];
  vtkDataSet* saved = slot;
  slot = this->Proxy;
  for (vtkIdType n = 0; n < order->GetNumberOfIds(); ++n)
  {
    // VTK draws the box of the brick's texture: its own cells and ghosts (the shader decides
    // which pieces are its own), so that no ray on a face between two bricks misses both.
    this->CurrentBrick = static_cast<int>(order->GetId(n));
    int points[6];
    this->GetBrickPoints(points);
    if (atlas)
    {
      const int* dims = input->GetDimensions();
      for (int a = 0; a < 3; ++a)
      {
        points[2 * a] = 0;
        points[2 * a + 1] = dims[a] - 1;
      }
    }
    double origin[3], spacing[3];
    input->TransformContinuousIndexToPhysicalPoint(
      extent[0] + points[0], extent[2] + points[2], extent[4] + points[4], origin);
    for (int a = 0; a < 3; ++a)
    {
      spacing[a] = input->GetSpacing()[a] * (points[2 * a + 1] - points[2 * a]);
    }
    this->Proxy->SetOrigin(origin);
    this->Proxy->SetSpacing(spacing);
    this->Proxy->Modified();
    this->Bricks->Activate(this->CurrentBrick);
    this->ActivateExtensionTextures();
    this->Superclass::GPURender(ren, vol);
    this->DeactivateExtensionTextures();
    this->Bricks->Deactivate(this->CurrentBrick);
  }
  slot = saved;
  this->CurrentBrick = 0;
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::SetTextureScalars(vtkDataArray* scalars)
{
  vtkSetObjectBodyMacro(TextureScalars, vtkDataArray, scalars);
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::PlaceTextureScalars(vtkDataArray* scalars)
{
  // vtkGPUVolumeRayCastMapper renders a shallow copy of the input that it makes again only
  // when the input changes; VTK's upload check (UpdateInputs) compares the array it finds
  // there with the one it uploaded last, so swapping it costs one upload, once.
  vtkImageData* copy = vtkImageData::SafeDownCast(this->GetTransformedInput(0));
  vtkDataSet* input = this->GetInput();
  if (!copy || !input)
  {
    return;
  }
  int cellFlag = 0, inputCellFlag = 0;
  vtkDataArray* current = vtkAbstractMapper::GetScalars(
    copy, this->ScalarMode, this->ArrayAccessMode, this->ArrayId, this->ArrayName, cellFlag);
  vtkDataArray* own = vtkAbstractMapper::GetScalars(
    input, this->ScalarMode, this->ArrayAccessMode, this->ArrayId, this->ArrayName, inputCellFlag);
  vtkDataArray* wanted = scalars ? scalars : own;
  if (!current || !wanted || current == wanted || cellFlag != inputCellFlag)
  {
    return;
  }
  vtkDataSetAttributes* attributes =
    cellFlag == 1 ? static_cast<vtkDataSetAttributes*>(copy->GetCellData()) : copy->GetPointData();
  if (attributes->GetScalars() == current)
  {
    attributes->SetScalars(wanted);
  }
  else
  {
    attributes->AddArray(wanted); // replaces the array of the same name
  }
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  this->ReleaseExtensionResources(window);
  this->Bricks->ReleaseGraphicsResources(window);
  this->DrawTimer->ReleaseGraphicsResources();
  this->Superclass::ReleaseGraphicsResources(window);
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::CoverWholeBounds(double bounds[6]) const
{
  const double* whole = this->WholeBounds;
  for (int a = 0; a < 3; ++a)
  {
    if (!(whole[2 * a] <= whole[2 * a + 1]) || !std::isfinite(whole[2 * a]) ||
      !std::isfinite(whole[2 * a + 1]))
    {
      return;
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    bounds[2 * a] = std::min(bounds[2 * a], whole[2 * a]);
    bounds[2 * a + 1] = std::max(bounds[2 * a + 1], whole[2 * a + 1]);
  }
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::DrawStockOwned(vtkRenderer* ren, vtkVolume* vol)
{
  // A piece with ghost points: VTK's own path draws the owned points alone (cropped to their
  // box), as the other pieces draw theirs, rather than the ghost points twice. The cropping is
  // set for this draw only, without marking the mapper modified but when it starts or stops,
  // so that VTK builds its shader with it once.
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  const int* owned = this->OwnedExtent;
  bool crop = input && owned[0] <= owned[1] && owned[2] <= owned[3] && owned[4] <= owned[5];
  double planes[6];
  if (crop)
  {
    int lo[3], hi[3];
    this->GetOwnedIndexBox(lo, hi);
    const int* extent = input->GetExtent();
    for (int c = 0; c < 8; ++c)
    {
      const double index[3] = { static_cast<double>(((c & 1) ? hi[0] : lo[0]) + extent[0]),
        static_cast<double>(((c & 2) ? hi[1] : lo[1]) + extent[2]),
        static_cast<double>(((c & 4) ? hi[2] : lo[2]) + extent[4]) };
      double point[3];
      input->TransformContinuousIndexToPhysicalPoint(index, point);
      for (int a = 0; a < 3; ++a)
      {
        planes[2 * a] = c == 0 ? point[a] : std::min(planes[2 * a], point[a]);
        planes[2 * a + 1] = c == 0 ? point[a] : std::max(planes[2 * a + 1], point[a]);
      }
    }
    if (this->Cropping)
    {
      // The user's sub-volume within the owned points; other region flags cannot be joined
      // with it.
      crop = this->CroppingRegionFlags == VTK_CROP_SUBVOLUME;
      for (int a = 0; a < 3 && crop; ++a)
      {
        planes[2 * a] = std::max(planes[2 * a], this->CroppingRegionPlanes[2 * a]);
        planes[2 * a + 1] = std::min(planes[2 * a + 1], this->CroppingRegionPlanes[2 * a + 1]);
      }
      if (!crop)
      {
        this->WarnFallbackOnce("VTK's own path cannot join cropping regions other than the "
                               "sub-volume with a piece's owned points: the piece's ghost "
                               "points are drawn too");
      }
    }
  }
  if (crop != this->StockCroppedToOwned)
  {
    this->StockCroppedToOwned = crop;
    this->Modified();
  }
  if (!crop)
  {
    this->Superclass::GPURender(ren, vol);
    return;
  }
  const vtkTypeBool cropping = this->Cropping;
  const int flags = this->CroppingRegionFlags;
  double userPlanes[6];
  std::copy(this->CroppingRegionPlanes, this->CroppingRegionPlanes + 6, userPlanes);
  this->Cropping = 1;
  this->CroppingRegionFlags = VTK_CROP_SUBVOLUME;
  std::copy(planes, planes + 6, this->CroppingRegionPlanes);
  this->Superclass::GPURender(ren, vol);
  this->Cropping = cropping;
  this->CroppingRegionFlags = flags;
  std::copy(userPlanes, userPlanes + 6, this->CroppingRegionPlanes);
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::GetWholeIndexBox(double lo[3], double hi[3])
{
  vtkVolumeImageAlgorithm::ComputeWholeIndexBox(
    vtkImageData::SafeDownCast(this->GetInput()), this->WholeBounds, lo, hi);
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::GetOwnedIndexBox(int lo[3], int hi[3])
{
  vtkVolumeImageAlgorithm::ComputeOwnedIndexBox(
    vtkImageData::SafeDownCast(this->GetInput()), this->OwnedExtent, lo, hi);
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ExtensionFrameCount: " << this->ExtensionFrameCount << "\n";
  os << indent << "LastDrawTime: " << this->LastDrawTime << "\n";
  os << indent << "MaximumTextureBytes: " << this->MaximumTextureBytes << "\n";
  os << indent << "MaximumBrickSize: " << this->MaximumBrickSize << "\n";
  os << indent << "ScalarRange: " << this->ScalarRange[0] << ", " << this->ScalarRange[1] << "\n";
  os << indent << "WholeBounds:";
  for (double b : this->WholeBounds)
  {
    os << " " << b;
  }
  os << "\n";
  os << indent << "OwnedExtent:";
  for (int e : this->OwnedExtent)
  {
    os << " " << e;
  }
  os << "\n";
  os << indent << "RayFrameInUse: " << this->RayFrameInUse << "\n";
  os << indent << "NumberOfBricks: " << this->Bricks->GetNumberOfBricks() << "\n";
}

//------------------------------------------------------------------------------
std::string vtkExtensibleGPUVolumeRayCastMapper::CheckTexture3D(vtkOpenGLRenderWindow* context,
  const int dims[3],
  double bytesPerTexel,
  const char* what)
{
  const int largest = context ? vtkTextureObject::GetMaximumTextureSize3D(context) : 0;
  std::ostringstream why;
  if (largest > 0 && std::max({ dims[0], dims[1], dims[2] }) > largest)
  {
    why << "the " << what << " (" << dims[0] << " x " << dims[1] << " x " << dims[2]
        << ") has an axis longer than the GPU's largest 3D texture (GL_MAX_3D_TEXTURE_SIZE "
        << largest << ")";
    return why.str();
  }
  const double bytes = bytesPerTexel * dims[0] * static_cast<double>(dims[1]) * dims[2];
  if (bytes > static_cast<double>(this->MaximumTextureBytes))
  {
    why << "the " << what << " (" << dims[0] << " x " << dims[1] << " x " << dims[2] << ", "
        << std::ceil(bytes / 1048576.0) << " MiB) exceeds MaximumTextureBytes ("
        << std::floor(this->MaximumTextureBytes / 1048576.0) << " MiB)";
    return why.str();
  }
  return std::string();
}

//------------------------------------------------------------------------------
bool vtkExtensibleGPUVolumeRayCastMapper::CreateTexture3D(vtkTextureObject* texture,
  vtkOpenGLRenderWindow* context,
  const int dims[3],
  int components,
  int vtkType,
  void* data,
  const char* what,
  std::string& why)
{
  why =
    this->CheckTexture3D(context, dims, components * vtkDataArray::GetDataTypeSize(vtkType), what);
  if (why.empty())
  {
    // Errors left by earlier calls are not this upload's.
    for (int n = 0; n < 16 && glGetError() != GL_NO_ERROR; ++n)
    {
    }
    texture->SetContext(context);
    const bool created =
      texture->Create3DFromRaw(dims[0], dims[1], dims[2], components, vtkType, data);
    const GLenum error = glGetError();
    if (!created || error != GL_NO_ERROR)
    {
      std::ostringstream message;
      message << "OpenGL could not create the " << what << " (" << dims[0] << " x " << dims[1]
              << " x " << dims[2] << ")";
      if (error == GL_OUT_OF_MEMORY)
      {
        message << ": out of memory";
      }
      else if (error != GL_NO_ERROR)
      {
        message << ": error 0x" << std::hex << error;
      }
      why = message.str();
    }
  }
  if (!why.empty())
  {
    texture->ReleaseGraphicsResources(context);
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkExtensibleGPUVolumeRayCastMapper::CheckFrameVolumeTexture(vtkRenderer* ren,
  vtkDataArray* uploaded)
{
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  int cellFlag = 0;
  vtkDataArray* own = input
    ? vtkAbstractMapper::GetScalars(
        input, this->ScalarMode, this->ArrayAccessMode, this->ArrayId, this->ArrayName, cellFlag)
    : nullptr;
  uploaded = uploaded ? uploaded : own;
  if (!uploaded)
  {
    return true; // VTK reports the missing input or scalars itself
  }
  int dims[3];
  input->GetDimensions(dims);
  for (int a = 0; cellFlag && a < 3; ++a)
  {
    dims[a] = std::max(dims[a] - 1, 1);
  }
  const std::string why = this->CheckVolumeTexture(ren, uploaded, dims);
  if (!why.empty())
  {
    vtkErrorMacro("Cannot draw the volume: " << why << ". Not drawing.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
std::string vtkExtensibleGPUVolumeRayCastMapper::CheckVolumeTexture(vtkRenderer* ren,
  vtkDataArray* uploaded,
  const int dims[3])
{
  // vtkVolumeTexture keeps 8-, 16- and 32-bit floating types and makes floats of the others.
  const int size = uploaded->GetDataTypeSize();
  const double bytes = uploaded->GetNumberOfComponents() *
    (uploaded->GetDataType() == VTK_FLOAT || size <= 2 ? size : 4);
  return this->CheckTexture3D(
    vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow()), dims, bytes, "volume texture");
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::GetTextureValueMapping(vtkDataArray* scalars,
  double& scale,
  double& shift,
  const double* cover)
{
  // vtkVolumeTexture uploads 8- and 16-bit integers as normalised textures (signed ones with
  // SNORM, clamped at -1) and floats as they are; wider types become floats rescaled so that
  // the finite range maps to [0, 1].
  shift = 0.0;
  switch (scalars->GetDataType())
  {
    case VTK_UNSIGNED_CHAR:
      scale = 255.0;
      break;
    case VTK_SIGNED_CHAR:
    case VTK_CHAR:
      scale = 127.0;
      break;
    case VTK_UNSIGNED_SHORT:
      scale = 65535.0;
      break;
    case VTK_SHORT:
      scale = 32767.0;
      break;
    case VTK_FLOAT:
      scale = 1.0;
      break;
    default:
    {
      double range[2], tableRange[2];
      if (!vtkPreIntegrationTable::ComputeScalarRange(scalars, range, tableRange, cover))
      {
        scalars->GetFiniteRange(range, 0);
      }
      // The range is rounded to float before VTK computes its scale.
      const double lo = static_cast<float>(range[0]);
      const double hi = static_cast<float>(range[1]);
      scale = hi > lo ? hi - lo : 1.0;
      shift = lo;
    }
  }
}

//------------------------------------------------------------------------------
vtkDataArray* vtkExtensibleGPUVolumeRayCastMapper::GetFrameScalars(int dims[3],
  int& cellFlag,
  FramePlan& plan)
{
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  cellFlag = 0;
  vtkDataArray* scalars = input
    ? vtkAbstractMapper::GetScalars(
        input, this->ScalarMode, this->ArrayAccessMode, this->ArrayId, this->ArrayName, cellFlag)
    : nullptr;
  if (!input || !scalars)
  {
    plan = DrawStock; // VTK reports the missing input or scalars itself.
    return nullptr;
  }
  input->GetDimensions(dims);
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2)
  {
    vtkErrorMacro("The volume needs at least 2 points along each axis to enclose a cell; it has "
      << dims[0] << " x " << dims[1] << " x " << dims[2] << "; not drawing.");
    plan = DrawNothing;
    return nullptr;
  }
  // VTK's texture upload reads as many values as the grid has, whatever the array holds.
  const vtkIdType expected = cellFlag ? input->GetNumberOfCells() : input->GetNumberOfPoints();
  std::string why = vtkVolumeImageAlgorithm::CheckGeometry(input);
  if (why.empty() && scalars->GetNumberOfTuples() != expected)
  {
    why = "The scalar array has " + std::to_string(scalars->GetNumberOfTuples()) + " values for " +
      std::to_string(expected) + (cellFlag ? " cells" : " points") +
      " of the grid; a truncated or mismatched file?";
  }
  for (int c = 0; why.empty() && c < scalars->GetNumberOfComponents(); ++c)
  {
    // VTK maps the texture through the range, which an infinite value makes infinite.
    double range[2], finite[2];
    scalars->GetRange(range, c);
    scalars->GetFiniteRange(finite, c);
    if (range[0] != finite[0] || range[1] != finite[1])
    {
      why = "The scalars hold infinite values; replace them by NaN or a finite fill value.";
    }
    else if (std::max(std::abs(finite[0]), std::abs(finite[1])) > VTK_FLOAT_MAX)
    {
      // The volume texture is float at most: such values would become infinite.
      why = "The scalar range exceeds float range, in which the volume texture holds it; "
            "rescale the values.";
    }
  }
  if (!why.empty())
  {
    vtkErrorMacro(<< why << " Not drawing.");
    plan = DrawNothing;
    return nullptr;
  }
  return scalars;
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::WarnEmptyOnce(const std::string& message)
{
  if (this->LastEmptyWarning != message)
  {
    vtkWarningMacro(<< message);
    this->LastEmptyWarning = message;
  }
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::WarnFallbackOnce(const char* reason)
{
  if (this->LastFallbackWarning != reason)
  {
    vtkWarningMacro(<< reason << "; drawing with VTK's stock shader.");
    this->LastFallbackWarning = reason;
  }
}

//------------------------------------------------------------------------------
double* vtkExtensibleGPUVolumeRayCastMapper::GetBounds()
{
  double* bounds = this->Superclass::GetBounds();
  vtkVolumeImageAlgorithm::ReportGeometry(
    this, vtkImageData::SafeDownCast(this->GetDataSetInput()), this->ReportedBoundsTime);
  return bounds;
}

namespace
{
// Copies the values of an array into a wider type, in parallel.
template <typename Out>
struct WideningCopier
{
  vtkDataArray* In;
  Out* Values;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    // Only 8- and 16-bit integers are widened; they have a standard memory layout.
    void* raw = this->In->GetVoidPointer(0);
    switch (this->In->GetDataType())
    {
      case VTK_UNSIGNED_CHAR:
        this->Copy(static_cast<const unsigned char*>(raw), begin, end);
        break;
      case VTK_SIGNED_CHAR:
        this->Copy(static_cast<const signed char*>(raw), begin, end);
        break;
      case VTK_CHAR:
        this->Copy(static_cast<const char*>(raw), begin, end);
        break;
      case VTK_UNSIGNED_SHORT:
        this->Copy(static_cast<const unsigned short*>(raw), begin, end);
        break;
      case VTK_SHORT:
        this->Copy(static_cast<const short*>(raw), begin, end);
        break;
    }
  }
  template <typename In>
  void Copy(const In* in, vtkIdType begin, vtkIdType end) const
  {
    std::copy(in + begin, in + end, this->Values + begin);
  }
};

template <typename Out>
void CopyWidened(vtkDataArray* in, vtkDataArray* out)
{
  WideningCopier<Out> copier{ in, static_cast<Out*>(out->GetVoidPointer(0)) };
  vtkSMPTools::For(0, in->GetNumberOfTuples(), copier);
}
}

//------------------------------------------------------------------------------
vtkDataArray* vtkExtensibleGPUVolumeRayCastMapper::WidenedTextureScalars(vtkDataArray* scalars,
  int wideType)
{
  const int type = scalars ? scalars->GetDataType() : VTK_VOID;
  const bool eightBit = type == VTK_UNSIGNED_CHAR || type == VTK_SIGNED_CHAR || type == VTK_CHAR;
  const bool sixteenBit = type == VTK_UNSIGNED_SHORT || type == VTK_SHORT;
  int copyType = VTK_VOID; // no copy
  if (wideType == VTK_FLOAT && (eightBit || sixteenBit))
  {
    copyType = VTK_FLOAT;
  }
  else if (wideType != VTK_FLOAT && eightBit)
  {
    copyType = type == VTK_UNSIGNED_CHAR ? VTK_UNSIGNED_SHORT : VTK_SHORT;
  }
  if (copyType == VTK_VOID || !scalars->HasStandardMemoryLayout() ||
    scalars->GetNumberOfComponents() != 1)
  {
    if (this->WidenedScalars)
    {
      this->WidenedScalars->Delete(); // no longer wanted
    }
    this->WidenedScalars = nullptr;
    this->WidenedSource = nullptr;
    return nullptr;
  }
  if (this->WidenedScalars && this->WidenedSource == scalars &&
    this->WidenedSourceTime == scalars->GetMTime() &&
    this->WidenedScalars->GetDataType() == copyType)
  {
    return this->WidenedScalars;
  }
  if (this->WidenedScalars)
  {
    this->WidenedScalars->Delete();
    this->WidenedScalars = nullptr;
    this->WidenedSource = nullptr;
  }
  const vtkIdType values = scalars->GetNumberOfTuples();
  vtkDataArray* copy = vtkDataArray::CreateDataArray(copyType);
  copy->SetName(scalars->GetName());
  bool ok = false;
  try
  {
    copy->SetNumberOfValues(values);
    ok = copy->GetNumberOfValues() == values;
  }
  catch (const std::bad_alloc&)
  {
  }
  if (!ok)
  {
    copy->Delete();
    vtkWarningMacro("Not enough memory for a "
      << (copyType == VTK_FLOAT ? 32 : 16) << "-bit copy of the volume ("
      << values * (copyType == VTK_FLOAT ? 4 : 2) << " bytes); uploading the data as it is.");
    return nullptr;
  }
  switch (copyType)
  {
    case VTK_FLOAT:
      CopyWidened<float>(scalars, copy);
      break;
    case VTK_SHORT:
      CopyWidened<short>(scalars, copy);
      break;
    default:
      CopyWidened<unsigned short>(scalars, copy);
  }
  this->WidenedScalars = copy;
  this->WidenedSource = scalars;
  this->WidenedSourceTime = scalars->GetMTime();
  return copy;
}

//------------------------------------------------------------------------------
std::string vtkExtensibleGPUVolumeRayCastMapper::GetCompositeFallbackReason(vtkVolume* vol,
  vtkDataArray* scalars,
  const char* method)
{
  const std::string subject = method;
  vtkVolumeProperty* property = vol->GetProperty();
  if (this->BlendMode != vtkVolumeMapper::COMPOSITE_BLEND)
  {
    return subject + " applies to composite blending only";
  }
  if (scalars->GetNumberOfComponents() != 1)
  {
    return subject + " needs single-component scalars";
  }
  if (property->GetTransferFunctionMode() != vtkVolumeProperty::TF_1D)
  {
    return subject + " does not support 2D transfer functions";
  }
  // A gradient opacity of 1 everywhere changes nothing; VTK creates that default as soon as
  // anything (vtkFixedPointVolumeRayCastMapper, for one) asks the property for the function.
  if (property->HasGradientOpacity(0) && !property->GetDisableGradientOpacity(0) &&
    !IsConstantOne(property->GetGradientOpacity(0)))
  {
    return subject + " does not support gradient opacity";
  }
  return std::string();
}

//------------------------------------------------------------------------------
bool vtkExtensibleGPUVolumeRayCastMapper::CheckFrameSampleDistance(double distance,
  double maximumSamples)
{
  if (!(distance > 0.0) || !std::isfinite(distance))
  {
    vtkErrorMacro(
      "The sample distance must be positive and finite, got " << distance << "; not drawing.");
    return false;
  }
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  if (!input)
  {
    return true; // no input: VTK reports it itself
  }
  double bounds[6];
  input->GetBounds(bounds);
  const double lo[3] = { bounds[0], bounds[2], bounds[4] };
  const double hi[3] = { bounds[1], bounds[3], bounds[5] };
  const double samples = std::sqrt(vtkMath::Distance2BetweenPoints(lo, hi)) / distance;
  if (samples > maximumSamples)
  {
    vtkErrorMacro("The sample distance "
      << distance << " takes " << samples << " samples along the volume's diagonal, more than "
      << maximumSamples << " (MaximumSamplesPerRay); not drawing.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkExtensibleGPUVolumeRayCastMapper::IsConstantOne(vtkPiecewiseFunction* function)
{
  const int n = function ? function->GetSize() : 0;
  double node[4];
  for (int i = 0; i < n; ++i)
  {
    function->GetNodeValue(i, node);
    if (node[1] != 1.0)
    {
      return false;
    }
  }
  return n > 0;
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::UpdateRayFrame(vtkRenderer* ren, vtkVolume* vol)
{
  // VTK's shader reaches a ray's points through float matrices from window to texture space,
  // with eye-space values of the camera's distance: a ray's points round at the scale of that
  // distance. The camera model gives each ray's point near the volume and its direction in
  // double, so float only rounds at the volume's own scale (a brick's, see
  // SetRayFrameUniforms).
  this->RayFrameInUse = 0;
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  vtkCamera* camera = ren->GetActiveCamera();
  int size[2], lowerLeft[2];
  ren->GetTiledSizeAndOrigin(&size[0], &size[1], &lowerLeft[0], &lowerLeft[1]);
  if (!input || !camera || size[0] < 1 || size[1] < 1)
  {
    return;
  }
  this->RayModel->SetCamera(camera);
  this->RayModel->SetImageSize(size);
  double frame[5][3];
  bool perspective = false;
  // 1e-9 in normalised device coordinates is far below a pixel.
  if (!this->RayModel->Prepare() || this->RayModel->ComputeProjectionMismatch() > 1e-9 ||
    !this->RayModel->GetGridRayFrame(
      input, vol->GetMatrix(), frame[0], frame[1], frame[2], frame[3], frame[4], perspective))
  {
    return;
  }
  for (int v = 0; v < 5; ++v)
  {
    std::copy(frame[v], frame[v] + 3, this->RayFrame[v]);
  }
  this->RayPixelCentre[0] = 0.5 * size[0];
  this->RayPixelCentre[1] = 0.5 * size[1];
  this->RayPerspective = perspective ? 1 : 0;
  this->RayFrameInUse = 1;
}

//------------------------------------------------------------------------------
void vtkExtensibleGPUVolumeRayCastMapper::SetRayFrameUniforms(vtkShaderProgram* program)
{
  program->SetUniformi("hovr_rayFrameInUse", this->RayFrameInUse);
  if (!this->RayFrameInUse)
  {
    return;
  }
  // The brick's frame: grid index from its texture's first point, and the pixel nearest to the
  // ray through the brick's centre as the frame's centre.
  int points[6];
  this->GetBrickPoints(points);
  const double(*f)[3] = this->RayFrame;
  double x[3], rhs[3], m[3][3];
  for (int a = 0; a < 3; ++a)
  {
    x[a] = 0.5 * (points[2 * a] + points[2 * a + 1]);
    // Solve p.x dx + p.y dy - l w = r for the pixel offset p of the ray through x.
    const double w = this->RayPerspective ? x[a] - f[3][a] : f[4][a];
    m[a][0] = f[1][a];
    m[a][1] = f[2][a];
    m[a][2] = -w;
    rhs[a] = (this->RayPerspective ? f[3][a] : x[a]) - f[0][a];
  }
  double pixel[2] = { 0.0, 0.0 };
  double along = this->RayPerspective ? 1.0 : 0.0; // l of the ray through the brick's centre
  const double det = vtkMath::Determinant3x3(m);
  if (std::abs(det) > 0.0)
  {
    for (int c = 0; c < 3; ++c)
    {
      double mc[3][3];
      for (int a = 0; a < 3; ++a)
      {
        std::copy(m[a], m[a] + 3, mc[a]);
        mc[a][c] = rhs[a];
      }
      const double value = vtkMath::Determinant3x3(mc) / det;
      if (c == 2)
      {
        along = std::isfinite(value) && (!this->RayPerspective || value > 0.0) ? value : along;
        continue;
      }
      pixel[c] = std::isfinite(value) ? std::round(std::max(-1e6, std::min(value, 1e6))) : 0.0;
    }
  }
  // The same pixel grid at the brick's depth (the plane of its centre, perpendicular to the
  // frame's): the frame's plane may lie far from the brick, where float positions round
  // coarsely. Perspective scales the plane about the eye by 1 / l, parallel moves it by l.
  const double scale = this->RayPerspective ? 1.0 / along : 1.0;
  float brickCentre[3], brickDx[3], brickDy[3];
  for (int a = 0; a < 3; ++a)
  {
    const double onPlane = f[0][a] + pixel[0] * f[1][a] + pixel[1] * f[2][a];
    const double atBrick =
      this->RayPerspective ? f[3][a] + scale * (onPlane - f[3][a]) : onPlane - along * f[4][a];
    brickCentre[a] = static_cast<float>(atBrick - points[2 * a]);
    brickDx[a] = static_cast<float>(scale * f[1][a]);
    brickDy[a] = static_cast<float>(scale * f[2][a]);
  }
  float centre[3], eye[3], local[3], localEye[3], dx[3], dy[3], forward[3];
  for (int a = 0; a < 3; ++a)
  {
    centre[a] = static_cast<float>(f[0][a]);
    eye[a] = static_cast<float>(f[3][a]);
    local[a] =
      static_cast<float>(f[0][a] + pixel[0] * f[1][a] + pixel[1] * f[2][a] - points[2 * a]);
    localEye[a] = static_cast<float>(f[3][a] - points[2 * a]);
    dx[a] = static_cast<float>(f[1][a]);
    dy[a] = static_cast<float>(f[2][a]);
    forward[a] = static_cast<float>(f[4][a]);
  }
  const float pixelCentre[2] = { static_cast<float>(this->RayPixelCentre[0]),
    static_cast<float>(this->RayPixelCentre[1]) };
  const float localPixelCentre[2] = { static_cast<float>(this->RayPixelCentre[0] + pixel[0]),
    static_cast<float>(this->RayPixelCentre[1] + pixel[1]) };
  program->SetUniform3f("hovr_rayCentre", centre);
  program->SetUniform3f("hovr_rayEye", eye);
  program->SetUniform2f("hovr_rayPixelCentre", pixelCentre);
  program->SetUniform3f("hovr_localCentre", local);
  program->SetUniform3f("hovr_localEye", localEye);
  program->SetUniform2f("hovr_localPixelCentre", localPixelCentre);
  program->SetUniform3f("hovr_rayDx", dx);
  program->SetUniform3f("hovr_rayDy", dy);
  program->SetUniform3f("hovr_brickCentre", brickCentre);
  program->SetUniform3f("hovr_brickDx", brickDx);
  program->SetUniform3f("hovr_brickDy", brickDy);
  program->SetUniform3f("hovr_rayForward", forward);
  program->SetUniformi("hovr_rayPerspective", this->RayPerspective);
}
