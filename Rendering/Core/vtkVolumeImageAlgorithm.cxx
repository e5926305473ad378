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
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>

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
vtkFloatArray* vtkVolumeImageAlgorithm::InitializeOutput(vtkImageData* output, bool clear)
{
  const int* size = this->RayModel->GetImageSize();
  const int width = std::max(size[0], 1), height = std::max(size[1], 1);
  output->SetExtent(0, width - 1, 0, height - 1, 0, 0);
  vtkNew<vtkFloatArray> rgba;
  rgba->SetName("RGBA");
  rgba->SetNumberOfComponents(4);
  rgba->SetNumberOfTuples(static_cast<vtkIdType>(width) * height);
  if (clear)
  {
    rgba->FillValue(0.0f);
  }
  output->GetPointData()->SetScalars(rgba);
  return rgba;
}

//------------------------------------------------------------------------------
vtkDataArray* vtkVolumeImageAlgorithm::PrepareFrame(vtkImageData* input,
  vtkInformationVector** inputVector,
  int dims[3])
{
  vtkDataArray* scalars = this->GetInputArrayToProcess(0, inputVector);
  if (!input || !scalars)
  {
    vtkErrorMacro("The input has no point scalars to render.");
    return nullptr;
  }
  if (scalars->GetNumberOfComponents() != 1)
  {
    vtkErrorMacro("Only single-component scalars can be rendered; array '"
      << (scalars->GetName() ? scalars->GetName() : "") << "' has "
      << scalars->GetNumberOfComponents() << " components.");
    return nullptr;
  }
  input->GetDimensions(dims);
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2)
  {
    vtkErrorMacro("The volume needs at least 2 points along each axis to enclose a cell; it has "
      << dims[0] << " x " << dims[1] << " x " << dims[2] << ".");
    return nullptr;
  }
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
  return scalars;
}

//------------------------------------------------------------------------------
void vtkVolumeImageAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "VolumeProperty: " << this->VolumeProperty << "\n";
  os << indent << "ImageSize: " << this->RayModel->GetImageSize()[0] << " "
     << this->RayModel->GetImageSize()[1] << "\n";
}
