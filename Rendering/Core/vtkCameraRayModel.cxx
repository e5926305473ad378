// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkCameraRayModel.h"

#include "vtkCamera.h"
#include "vtkGridRayTraversal.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkCameraRayModel);
vtkCxxSetObjectMacro(vtkCameraRayModel, Camera, vtkCamera);

//------------------------------------------------------------------------------
vtkCameraRayModel::vtkCameraRayModel() = default;

//------------------------------------------------------------------------------
vtkCameraRayModel::~vtkCameraRayModel()
{
  this->SetCamera(nullptr);
}

//------------------------------------------------------------------------------
vtkMTimeType vtkCameraRayModel::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  return this->Camera ? std::max(t, this->Camera->GetMTime()) : t;
}

//------------------------------------------------------------------------------
bool vtkCameraRayModel::Prepare()
{
  if (!this->Camera)
  {
    vtkErrorMacro("No camera was given.");
    return false;
  }
  if (this->ImageSize[0] < 1 || this->ImageSize[1] < 1)
  {
    vtkErrorMacro("The image size must be at least 1 x 1, got " << this->ImageSize[0] << " x "
                                                                << this->ImageSize[1] << ".");
    return false;
  }
  double focal[3], viewUp[3];
  this->Camera->GetPosition(this->Position);
  this->Camera->GetFocalPoint(focal);
  this->Camera->GetViewUp(viewUp);
  vtkMath::Subtract(focal, this->Position, this->Forward);
  if (vtkMath::Normalize(this->Forward) == 0.0)
  {
    vtkErrorMacro("The camera position equals its focal point.");
    return false;
  }
  vtkMath::Cross(this->Forward, viewUp, this->Right);
  if (vtkMath::Normalize(this->Right) < 1e-12)
  {
    vtkErrorMacro("The camera view up is parallel to the view direction.");
    return false;
  }
  vtkMath::Cross(this->Right, this->Forward, this->Up);
  const double aspect = static_cast<double>(this->ImageSize[0]) / this->ImageSize[1];
  this->Parallel = this->Camera->GetParallelProjection() != 0;
  if (this->Parallel)
  {
    this->HalfHeight = this->Camera->GetParallelScale();
    if (!(this->HalfHeight > 0.0))
    {
      vtkErrorMacro("The parallel scale must be positive, got " << this->HalfHeight << ".");
      return false;
    }
  }
  else
  {
    const double angle = this->Camera->GetViewAngle();
    if (!(angle > 0.0 && angle < 180.0))
    {
      vtkErrorMacro("The view angle must lie in (0, 180) degrees, got " << angle << ".");
      return false;
    }
    // vtkCamera's view angle is vertical unless UseHorizontalViewAngle is on.
    const double tangent = std::tan(vtkMath::RadiansFromDegrees(angle) / 2.0);
    const bool horizontal = this->Camera->GetUseHorizontalViewAngle() != 0;
    this->HalfHeight = horizontal ? tangent / aspect : tangent;
  }
  this->HalfWidth = this->HalfHeight * aspect;
  return true;
}

//------------------------------------------------------------------------------
void vtkCameraRayModel::GetRay(double x, double y, double origin[3], double direction[3]) const
{
  for (int c = 0; c < 3; ++c)
  {
    const double offset = x * this->HalfWidth * this->Right[c] + y * this->HalfHeight * this->Up[c];
    if (this->Parallel)
    {
      origin[c] = this->Position[c] + offset;
      direction[c] = this->Forward[c];
    }
    else
    {
      origin[c] = this->Position[c];
      direction[c] = this->Forward[c] + offset;
    }
  }
  vtkMath::Normalize(direction);
}

//------------------------------------------------------------------------------
void vtkCameraRayModel::GetPixelRay(int i, int j, double origin[3], double direction[3]) const
{
  const double x = 2.0 * (i + 0.5) / this->ImageSize[0] - 1.0;
  const double y = 2.0 * (j + 0.5) / this->ImageSize[1] - 1.0;
  this->GetRay(x, y, origin, direction);
}

//------------------------------------------------------------------------------
vtkIdType vtkCameraRayModel::CountFixedStepSamples(vtkImageData* volume, double step) const
{
  if (!volume || !(step > 0.0))
  {
    return -1;
  }
  double bounds[6];
  volume->GetBounds(bounds);
  const double lo[3] = { bounds[0], bounds[2], bounds[4] };
  const double hi[3] = { bounds[1], bounds[3], bounds[5] };
  vtkIdType count = 0;
  for (int j = 0; j < this->ImageSize[1]; ++j)
  {
    for (int i = 0; i < this->ImageSize[0]; ++i)
    {
      double origin[3], direction[3];
      this->GetPixelRay(i, j, origin, direction);
      double t0 = 0.0, t1 = VTK_DOUBLE_MAX;
      if (vtkGridRayTraversal::ClipToBox(lo, hi, origin, direction, t0, t1))
      {
        count += static_cast<vtkIdType>(std::floor((t1 - t0) / step));
      }
    }
  }
  return count;
}

//------------------------------------------------------------------------------
void vtkCameraRayModel::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Camera: " << this->Camera << "\n";
  os << indent << "ImageSize: " << this->ImageSize[0] << " " << this->ImageSize[1] << "\n";
}
