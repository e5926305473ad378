// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkVolumeImageAlgorithm.h"

#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkDataArray.h"
#include "vtkErrorForwarder.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <vtksys/SystemInformation.hxx>

#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>

vtkCxxSetObjectMacro(vtkVolumeImageAlgorithm, VolumeProperty, vtkVolumeProperty);

//------------------------------------------------------------------------------
vtkVolumeImageAlgorithm::vtkVolumeImageAlgorithm()
  : RayModel(vtkCameraRayModel::New())
  , Sampler(vtkVolumeTransferFunctionSampler::New())
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
  vtkErrorForwarder::Forward(this->RayModel, this);
  vtkErrorForwarder::Forward(this->Sampler, this);
}

//------------------------------------------------------------------------------
vtkVolumeImageAlgorithm::~vtkVolumeImageAlgorithm()
{
  this->SetVolumeProperty(nullptr);
  this->RayModel->Delete();
  this->Sampler->Delete();
}

//------------------------------------------------------------------------------
void vtkVolumeImageAlgorithm::SetCamera(vtkCamera* camera)
{
  this->RayModel->SetCamera(camera);
  this->Modified();
}

//------------------------------------------------------------------------------
vtkCamera* vtkVolumeImageAlgorithm::GetCamera()
{
  return this->RayModel->GetCamera();
}

//------------------------------------------------------------------------------
void vtkVolumeImageAlgorithm::SetImageSize(int w, int h)
{
  const int* size = this->RayModel->GetImageSize();
  if (size[0] != w || size[1] != h)
  {
    this->RayModel->SetImageSize(w, h);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int* vtkVolumeImageAlgorithm::GetImageSize()
{
  return this->RayModel->GetImageSize();
}

//------------------------------------------------------------------------------
vtkMTimeType vtkVolumeImageAlgorithm::GetMTime()
{
  vtkMTimeType t = std::max(this->Superclass::GetMTime(), this->RayModel->GetMTime());
  if (this->VolumeProperty)
  {
    t = std::max(t, this->VolumeProperty->GetMTime());
    this->Sampler->SetFromVolumeProperty(this->VolumeProperty);
    t = std::max(t, this->Sampler->GetMTime());
  }
  return t;
}

//------------------------------------------------------------------------------
int vtkVolumeImageAlgorithm::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkVolumeImageAlgorithm::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int* size = this->RayModel->GetImageSize();
  int extent[6] = { 0, std::max(size[0], 1) - 1, 0, std::max(size[1], 1) - 1, 0, 0 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  double origin[3] = { 0, 0, 0 }, spacing[3] = { 1, 1, 1 };
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, VTK_FLOAT, 4);
  return 1;
}

//------------------------------------------------------------------------------
int vtkVolumeImageAlgorithm::RequestUpdateExtent(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector*)
{
  // Every ray may cross the whole volume.
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
    inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()),
    6);
  return 1;
}

//------------------------------------------------------------------------------
vtkFloatArray* vtkVolumeImageAlgorithm::InitializeOutput(vtkImageData* output,
  bool clear,
  int extraFloats)
{
  const int* size = this->RayModel->GetImageSize();
  const int width = std::max(size[0], 1), height = std::max(size[1], 1);
  const double bytes = static_cast<double>(width) * height * (4.0 + extraFloats) * sizeof(float);
  // The allocation itself may succeed by overcommit and the first write kill the process.
  vtksys::SystemInformation system;
  system.RunMemoryCheck();
  const double memory = 1048576.0 * static_cast<double>(system.GetTotalPhysicalMemory()); // MiB
  vtkNew<vtkFloatArray> rgba;
  rgba->SetName("RGBA");
  rgba->SetNumberOfComponents(4);
  bool allocated = memory <= 0.0 || bytes < memory;
  if (allocated)
  {
    try
    {
      allocated = rgba->Resize(static_cast<vtkIdType>(width) * height) != 0;
    }
    catch (const std::bad_alloc&)
    {
      allocated = false;
    }
  }
  if (!allocated)
  {
    output->Initialize();
    vtkErrorMacro("A " << width << " x " << height << " image needs "
                       << std::ceil(bytes / 1048576.0)
                       << " MiB, more than this machine can allocate ("
                       << std::floor(memory / 1048576.0) << " MiB of memory).");
    return nullptr;
  }
  rgba->SetNumberOfTuples(static_cast<vtkIdType>(width) * height);
  output->SetExtent(0, width - 1, 0, height - 1, 0, 0);
  if (clear)
  {
    rgba->FillValue(0.0f);
  }
  output->GetPointData()->SetScalars(rgba);
  return rgba;
}

//------------------------------------------------------------------------------
namespace
{
// Smallest volume diagonal that is rendered: 1e5 times vtkCamera's least distance to its
// focal point.
constexpr double MinimumDiagonal = 1e-15;
}

//------------------------------------------------------------------------------
std::string vtkVolumeImageAlgorithm::CheckGeometry(vtkImageData* input)
{
  std::ostringstream why;
  const double* origin = input->GetOrigin();
  const double* spacing = input->GetSpacing();
  const double* direction = input->GetDirectionMatrix()->GetData();
  const bool finite = std::all_of(origin, origin + 3, [](double x) { return std::isfinite(x); }) &&
    std::all_of(spacing, spacing + 3, [](double x) { return std::isfinite(x) && x != 0.0; }) &&
    std::all_of(direction, direction + 9, [](double x) { return std::isfinite(x); });
  const double determinant = vtkMatrix3x3::Determinant(direction);
  double bounds[6];
  input->GetBounds(bounds);
  const bool bounded = std::all_of(bounds, bounds + 6, [](double x) { return std::isfinite(x); }) &&
    std::isfinite(bounds[1] - bounds[0]) && std::isfinite(bounds[3] - bounds[2]) &&
    std::isfinite(bounds[5] - bounds[4]);
  const double* toIndex = input->GetPhysicalToIndexMatrix()->GetData();
  if (!finite || !(std::abs(determinant) > 1e-12) || !bounded ||
    !std::all_of(toIndex, toIndex + 16, [](double x) { return std::isfinite(x); }))
  {
    why << "The volume's geometry cannot be rendered: origin (" << origin[0] << ", " << origin[1]
        << ", " << origin[2] << "), spacing (" << spacing[0] << ", " << spacing[1] << ", "
        << spacing[2] << "), direction matrix determinant " << determinant
        << "; they must be finite, the spacing non-zero, the direction matrix invertible and the "
           "bounds within double range.";
    return why.str();
  }
  const double diagonal = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
    (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  if (!(diagonal >= MinimumDiagonal))
  {
    // vtkCamera keeps at least 1e-20 from its focal point: too far to frame a smaller volume.
    why << "The volume is " << diagonal << " across, less than " << MinimumDiagonal
        << ": no vtkCamera can frame it; scale the spacing.";
    return why.str();
  }
  return std::string();
}

//------------------------------------------------------------------------------
void vtkVolumeImageAlgorithm::ReportGeometry(vtkObject* reporter,
  vtkImageData* input,
  vtkMTimeType& reported)
{
  if (!input || input->GetMTime() == reported)
  {
    return;
  }
  reported = input->GetMTime();
  const std::string why = CheckGeometry(input);
  if (!why.empty())
  {
    vtkErrorWithObjectMacro(reporter, << why << " Not drawing.");
  }
}

//------------------------------------------------------------------------------
std::string vtkVolumeImageAlgorithm::CheckVolume(vtkImageData* input, vtkDataArray* scalars)
{
  std::ostringstream why;
  if (!input || !scalars)
  {
    return "The input has no point scalars to render.";
  }
  if (scalars->GetNumberOfComponents() != 1)
  {
    why << "Only single-component scalars can be rendered; array '"
        << (scalars->GetName() ? scalars->GetName() : "") << "' has "
        << scalars->GetNumberOfComponents() << " components.";
    return why.str();
  }
  int dims[3];
  input->GetDimensions(dims);
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2)
  {
    why << "The volume needs at least 2 points along each axis to enclose a cell; it has "
        << dims[0] << " x " << dims[1] << " x " << dims[2] << ".";
    return why.str();
  }
  const vtkIdType points = static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2];
  if (scalars->GetNumberOfTuples() != points)
  {
    why << "The scalar array '" << (scalars->GetName() ? scalars->GetName() : "") << "' has "
        << scalars->GetNumberOfTuples() << " values for the " << dims[0] << " x " << dims[1]
        << " x " << dims[2] << " = " << points
        << " points of the grid; a truncated or mismatched file?";
    return why.str();
  }
  const std::string geometry = CheckGeometry(input);
  if (!geometry.empty())
  {
    return geometry;
  }
  double range[2], finiteRange[2];
  scalars->GetRange(range, 0);
  scalars->GetFiniteRange(finiteRange, 0);
  if (!(finiteRange[0] <= finiteRange[1]))
  {
    return "The scalars hold no finite value (all NaN or infinite): nothing can be drawn.";
  }
  if (range[0] != finiteRange[0] || range[1] != finiteRange[1])
  {
    return "The scalars hold infinite values; replace them by NaN (drawn transparent) or by a "
           "finite fill value.";
  }
  if (!std::isfinite(finiteRange[1] - finiteRange[0]))
  {
    why << "The scalar range [" << finiteRange[0] << ", " << finiteRange[1]
        << "] is wider than the largest double; rescale the values.";
    return why.str();
  }
  return std::string();
}

//------------------------------------------------------------------------------
vtkDataArray* vtkVolumeImageAlgorithm::PrepareFrame(vtkImageData* input,
  vtkInformationVector** inputVector,
  int dims[3])
{
  this->FrameWarned = false;
  vtkDataArray* scalars = this->GetInputArrayToProcess(0, inputVector);
  const std::string why = CheckVolume(input, scalars);
  if (!why.empty())
  {
    vtkErrorMacro(<< why);
    return nullptr;
  }
  input->GetDimensions(dims);
  if (!this->VolumeProperty)
  {
    vtkErrorMacro("No volume property (transfer functions) was given.");
    return nullptr;
  }
  this->Sampler->SetFromVolumeProperty(this->VolumeProperty);
  if (!this->Sampler->Prepare() || !this->RayModel->Prepare())
  {
    return nullptr;
  }
  double range[2];
  scalars->GetFiniteRange(range, 0);
  if (!(this->Sampler->GetMaximumOpacity(range[0], range[1]) > 0.0))
  {
    vtkWarningMacro("The scalar opacity is zero over the data range ["
      << range[0] << ", " << range[1] << "]: the image is transparent.");
    this->FrameWarned = true;
  }
  return scalars;
}

//------------------------------------------------------------------------------
bool vtkVolumeImageAlgorithm::CheckSampleDistance(vtkImageData* input,
  double step,
  double maximumSamples)
{
  if (!(step > 0.0) || !std::isfinite(step))
  {
    vtkErrorMacro("The sample distance must be positive and finite, got " << step << ".");
    return false;
  }
  const double diagonal = input->GetLength(); // of the bounds
  if (step > diagonal)
  {
    vtkErrorMacro("The sample distance " << step << " exceeds the volume's diagonal (" << diagonal
                                         << "): rays would step over the volume.");
    return false;
  }
  const double samples = diagonal / step;
  if (!(samples <= maximumSamples))
  {
    vtkErrorMacro("The sample distance " << step << " takes " << samples
                                         << " samples along the volume's diagonal, more than "
                                         << maximumSamples << " (MaximumSamplesPerRay).");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkVolumeImageAlgorithm::WarnIfTransparent(vtkFloatArray* rgba)
{
  const float* p = rgba->GetPointer(0);
  const vtkIdType n = rgba->GetNumberOfTuples();
  for (vtkIdType i = 0; i < n; ++i)
  {
    if (p[4 * i + 3] > 0.0f)
    {
      return;
    }
  }
  if (!this->FrameWarned)
  {
    vtkWarningMacro("The image is transparent: no pixel ray meets a visible part of the volume. "
                    "Check the camera (does it frame the volume?), the opacity transfer function "
                    "and the opacity unit distance.");
  }
}

//------------------------------------------------------------------------------
bool vtkVolumeImageAlgorithm::ReadNormalArray(vtkImageData* input,
  const char* name,
  vtkIdType n,
  std::vector<double>& normals)
{
  vtkDataArray* array = name ? input->GetPointData()->GetArray(name) : nullptr;
  if (!array || array->GetNumberOfComponents() != 3 || array->GetNumberOfTuples() != n)
  {
    vtkErrorMacro("NormalArrayName \"" << (name ? name : "")
                                       << "\" names no point array of 3-component vectors, "
                                          "one per point; the image is empty.");
    return false;
  }
  normals.resize(3 * static_cast<size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    array->GetTuple(i, normals.data() + 3 * i);
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkVolumeImageAlgorithm::ComputeWholeIndexBox(vtkImageData* input,
  const double wholeBounds[6],
  double lo[3],
  double hi[3])
{
  int dims[3] = { 1, 1, 1 };
  if (input)
  {
    input->GetDimensions(dims);
  }
  for (int a = 0; a < 3; ++a)
  {
    lo[a] = 0.0;
    hi[a] = dims[a] - 1.0;
  }
  if (!input)
  {
    return;
  }
  double whole[6];
  input->GetBounds(whole);
  bool valid = true;
  for (int a = 0; a < 3; ++a)
  {
    valid = valid && wholeBounds[2 * a] <= wholeBounds[2 * a + 1] &&
      std::isfinite(wholeBounds[2 * a]) && std::isfinite(wholeBounds[2 * a + 1]);
  }
  for (int a = 0; a < 3 && valid; ++a)
  {
    // Widened, so that the box holds the input's points.
    whole[2 * a] = std::min(whole[2 * a], wholeBounds[2 * a]);
    whole[2 * a + 1] = std::max(whole[2 * a + 1], wholeBounds[2 * a + 1]);
  }
  if (!(whole[0] <= whole[1]))
  {
    return;
  }
  const int* extent = input->GetExtent();
  for (int c = 0; c < 8; ++c)
  {
    const double corner[3] = { whole[c & 1], whole[2 + ((c >> 1) & 1)], whole[4 + ((c >> 2) & 1)] };
    double index[3];
    input->TransformPhysicalPointToContinuousIndex(corner, index);
    for (int a = 0; a < 3; ++a)
    {
      // Whole points: the pieces' bounds lie on the grid.
      const double i = std::round(index[a]) - extent[2 * a];
      lo[a] = c == 0 ? i : std::min(lo[a], i);
      hi[a] = c == 0 ? i : std::max(hi[a], i);
    }
  }
}

//------------------------------------------------------------------------------
void vtkVolumeImageAlgorithm::ComputeOwnedIndexBox(vtkImageData* input,
  const int ownedExtent[6],
  int lo[3],
  int hi[3])
{
  int extent[6] = { 0, 0, 0, 0, 0, 0 };
  if (input)
  {
    input->GetExtent(extent);
  }
  const int* owned = ownedExtent;
  const bool some = owned[0] <= owned[1] && owned[2] <= owned[3] && owned[4] <= owned[5];
  for (int a = 0; a < 3; ++a)
  {
    lo[a] = some ? std::max(owned[2 * a], extent[2 * a]) - extent[2 * a] : 0;
    hi[a] =
      (some ? std::min(owned[2 * a + 1], extent[2 * a + 1]) : extent[2 * a + 1]) - extent[2 * a];
  }
}

//------------------------------------------------------------------------------
void vtkVolumeImageAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "VolumeProperty: " << this->VolumeProperty << "\n";
  os << indent << "ImageSize: " << this->RayModel->GetImageSize()[0] << " "
     << this->RayModel->GetImageSize()[1] << "\n";
}
