// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkRGBAErrorMetrics.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <algorithm>
#include <cmath>
#include <limits>

vtkStandardNewMacro(vtkRGBAErrorMetrics);

//------------------------------------------------------------------------------
vtkRGBAErrorMetrics::vtkRGBAErrorMetrics()
{
  this->SetNumberOfInputPorts(2);
  this->SetArrayName("RGBA");
}

//------------------------------------------------------------------------------
vtkRGBAErrorMetrics::~vtkRGBAErrorMetrics()
{
  this->SetArrayName(nullptr);
}

//------------------------------------------------------------------------------
double vtkRGBAErrorMetrics::GetChannelRMSE(int channel) const
{
  return channel >= 0 && channel < 4 ? this->ChannelRMSE[channel] : -1.0;
}

//------------------------------------------------------------------------------
double vtkRGBAErrorMetrics::GetChannelMaximumError(int channel) const
{
  return channel >= 0 && channel < 4 ? this->ChannelMaximumError[channel] : -1.0;
}

//------------------------------------------------------------------------------
int vtkRGBAErrorMetrics::FillInputPortInformation(int port, vtkInformation* info)
{
  this->Superclass::FillInputPortInformation(port, info);
  // Optional for the pipeline so that RequestData runs without one of the images: it reports
  // the missing image and resets the metrics to -1 instead of leaving the last values.
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkRGBAErrorMetrics::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkDataObject::SetPointDataActiveScalarInfo(outputVector->GetInformationObject(0), VTK_FLOAT, 4);
  return 1;
}

//------------------------------------------------------------------------------
int vtkRGBAErrorMetrics::RequestUpdateExtent(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector*)
{
  // Each image whole, whatever its size: images of different sizes are an error of
  // RequestData's, not a pipeline error about extents.
  for (int port = 0; port < 2; ++port)
  {
    vtkInformation* info = inputVector[port]->GetInformationObject(0);
    if (info && info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    {
      info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
        info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()),
        6);
    }
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkRGBAErrorMetrics::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  this->RMSE = this->MaximumError = -1.0;
  this->NumberOfMeasuredPixels = 0;
  std::fill(this->ChannelRMSE, this->ChannelRMSE + 4, -1.0);
  std::fill(this->ChannelMaximumError, this->ChannelMaximumError + 4, -1.0);
  vtkImageData* test = vtkImageData::GetData(inputVector[0]);
  vtkImageData* reference = vtkImageData::GetData(inputVector[1]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  if (!test || !reference)
  {
    vtkErrorMacro("Both a test image and a reference image are needed.");
    return 1;
  }
  int dt[3], dr[3];
  test->GetDimensions(dt);
  reference->GetDimensions(dr);
  if (!std::equal(dt, dt + 3, dr))
  {
    vtkErrorMacro("Image sizes differ: " << dt[0] << "x" << dt[1] << "x" << dt[2] << " against "
                                         << dr[0] << "x" << dr[1] << "x" << dr[2] << ".");
    return 1;
  }
  vtkDataArray* a = test->GetPointData()->GetArray(this->ArrayName);
  vtkDataArray* b = reference->GetPointData()->GetArray(this->ArrayName);
  if (!a || !b || a->GetNumberOfComponents() != 4 || b->GetNumberOfComponents() != 4)
  {
    vtkErrorMacro("Both images need a 4-component point array named '" << this->ArrayName << "'.");
    return 1;
  }
  const vtkIdType n = a->GetNumberOfTuples();
  output->SetExtent(test->GetExtent());
  output->SetOrigin(test->GetOrigin());
  output->SetSpacing(test->GetSpacing());
  vtkNew<vtkFloatArray> diff;
  diff->SetName("Difference");
  diff->SetNumberOfComponents(4);
  diff->SetNumberOfTuples(n);
  double sum[4] = { 0, 0, 0, 0 };
  double peak[4] = { 0, 0, 0, 0 };
  vtkIdType measured = 0;
  for (vtkIdType i = 0; i < n; ++i)
  {
    // A reference pixel with a NaN channel was not computed (a sampled reference).
    bool computed = true;
    for (int c = 0; c < 4; ++c)
    {
      computed = computed && !std::isnan(b->GetComponent(i, c));
    }
    for (int c = 0; c < 4; ++c)
    {
      const double d = computed ? std::abs(a->GetComponent(i, c) - b->GetComponent(i, c))
                                : std::numeric_limits<double>::quiet_NaN();
      diff->SetTypedComponent(i, c, static_cast<float>(d));
      if (computed)
      {
        sum[c] += d * d;
        peak[c] = std::max(peak[c], d);
      }
    }
    measured += computed ? 1 : 0;
  }
  this->NumberOfMeasuredPixels = measured;
  output->GetPointData()->SetScalars(diff);
  double total = 0.0;
  this->MaximumError = 0.0;
  for (int c = 0; c < 4; ++c)
  {
    this->ChannelRMSE[c] = measured > 0 ? std::sqrt(sum[c] / measured) : 0.0;
    this->ChannelMaximumError[c] = peak[c];
    this->MaximumError = std::max(this->MaximumError, peak[c]);
    total += sum[c];
  }
  this->RMSE = measured > 0 ? std::sqrt(total / (4.0 * measured)) : 0.0;
  return 1;
}

//------------------------------------------------------------------------------
void vtkRGBAErrorMetrics::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ArrayName: " << (this->ArrayName ? this->ArrayName : "(none)") << "\n";
  os << indent << "RMSE: " << this->RMSE << "\n";
  os << indent << "MaximumError: " << this->MaximumError << "\n";
  os << indent << "NumberOfMeasuredPixels: " << this->NumberOfMeasuredPixels << "\n";
}
