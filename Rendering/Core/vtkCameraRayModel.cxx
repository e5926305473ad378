// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkCameraRayModel.h"

#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkGridRayTraversal.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"

#include <algorithm>
#include <cmath>
#include <limits>

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
  auto finite = [](const double v[3])
  { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); };
  if (!finite(this->Position) || !finite(focal) || !finite(viewUp))
  {
    vtkErrorMacro("The camera's position, focal point and view up must be finite.");
    return false;
  }
  vtkMath::Subtract(focal, this->Position, this->Forward);
  const double distance = vtkMath::Normalize(this->Forward);
  if (distance == 0.0)
  {
    vtkErrorMacro("The camera position equals its focal point.");
    return false;
  }
  if (distance <= 1.000001e-20)
  {
    // vtkCamera moves a focal point nearer than this away, which tilts its view up.
    vtkErrorMacro("The camera is " << distance
                                   << " from its focal point, at or below vtkCamera's smallest "
                                      "distance (1e-20): scale the volume's spacing up.");
    return false;
  }
  if (!std::isfinite(distance))
  {
    vtkErrorMacro("The camera's distance to its focal point overflows double precision.");
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
    if (!(this->HalfHeight > 0.0) || !std::isfinite(this->HalfHeight))
    {
      vtkErrorMacro(
        "The parallel scale must be positive and finite, got " << this->HalfHeight << ".");
      return false;
    }
    // Parallel rays start on the camera's plane, offset from its position by whole pixels: a
    // pixel below the rounding of the position would give every pixel the same ray.
    const double pixel = 2.0 * this->HalfHeight / this->ImageSize[1];
    const double position = std::max(
      { std::abs(this->Position[0]), std::abs(this->Position[1]), std::abs(this->Position[2]) });
    if (!(pixel > std::ldexp(position, -40)))
    {
      vtkErrorMacro("A pixel of the parallel projection ("
        << pixel << " world units) is below the precision of the camera's position (at " << position
        << "): move the camera closer to the volume or widen the parallel scale.");
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
vtkIdType vtkCameraRayModel::CountCellVisits(vtkImageData* volume) const
{
  if (!volume)
  {
    return -1;
  }
  int dims[3];
  volume->GetDimensions(dims);
  const int* extent = volume->GetExtent();
  const double* m = volume->GetPhysicalToIndexMatrix()->GetData();
  vtkIdType count = 0;
  for (int j = 0; j < this->ImageSize[1]; ++j)
  {
    for (int i = 0; i < this->ImageSize[0]; ++i)
    {
      double origin[3], direction[3], o[3], v[3];
      this->GetPixelRay(i, j, origin, direction);
      for (int r = 0; r < 3; ++r)
      {
        o[r] = m[4 * r] * origin[0] + m[4 * r + 1] * origin[1] + m[4 * r + 2] * origin[2] +
          m[4 * r + 3] - extent[2 * r];
        v[r] = m[4 * r] * direction[0] + m[4 * r + 1] * direction[1] + m[4 * r + 2] * direction[2];
      }
      vtkGridRayTraversal walk;
      if (walk.Initialize(dims, o, v, 0.0, VTK_DOUBLE_MAX))
      {
        int cell[3];
        double t0, t1;
        while (walk.Next(cell, t0, t1))
        {
          ++count;
        }
      }
    }
  }
  return count;
}

//------------------------------------------------------------------------------
void vtkCameraRayModel::ComputeDepths(vtkImageData* volume,
  vtkDataArray* positions,
  vtkDoubleArray* depth) const
{
  const vtkIdType n = static_cast<vtkIdType>(this->ImageSize[0]) * this->ImageSize[1];
  if (!volume || !positions || !depth || positions->GetNumberOfComponents() != 4 ||
    positions->GetNumberOfTuples() != n)
  {
    vtkErrorMacro("ComputeDepths needs a volume, W x H positions of 4 components and an "
                  "output array.");
    return;
  }
  depth->SetNumberOfComponents(1);
  depth->SetNumberOfTuples(n);
  const int* extent = volume->GetExtent();
  const double* m = volume->GetIndexToPhysicalMatrix()->GetData();
  for (vtkIdType p = 0; p < n; ++p)
  {
    double q[4];
    positions->GetTuple(p, q);
    if (!(q[3] > 0.0))
    {
      depth->SetValue(p, std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    double origin[3], direction[3], world[3];
    this->GetPixelRay(static_cast<int>(p % this->ImageSize[0]),
      static_cast<int>(p / this->ImageSize[0]),
      origin,
      direction);
    const double index[3] = { q[0] + extent[0], q[1] + extent[2], q[2] + extent[4] };
    double d = 0.0;
    for (int r = 0; r < 3; ++r)
    {
      world[r] =
        m[4 * r] * index[0] + m[4 * r + 1] * index[1] + m[4 * r + 2] * index[2] + m[4 * r + 3];
      d += (world[r] - origin[r]) * direction[r];
    }
    depth->SetValue(p, d);
  }
}

//------------------------------------------------------------------------------
bool vtkCameraRayModel::GetGridRayFrame(vtkImageData* volume,
  vtkMatrix4x4* propMatrix,
  double centre[3],
  double dx[3],
  double dy[3],
  double eye[3],
  double forward[3],
  bool& perspective) const
{
  if (!volume)
  {
    return false;
  }
  // World to grid index: the volume's physical-to-index map after the prop's inverse.
  vtkNew<vtkMatrix4x4> toIndex;
  if (propMatrix)
  {
    if (propMatrix->Determinant() == 0.0)
    {
      return false;
    }
    vtkMatrix4x4::Invert(propMatrix, toIndex);
  }
  vtkMatrix4x4::Multiply4x4(volume->GetPhysicalToIndexMatrix(), toIndex, toIndex);
  const int* extent = volume->GetExtent();
  for (int r = 0; r < 3; ++r)
  {
    toIndex->SetElement(r, 3, toIndex->GetElement(r, 3) - extent[2 * r]);
  }
  auto point = [&](const double w[3], double g[3])
  {
    const double in[4] = { w[0], w[1], w[2], 1.0 };
    double out[4];
    toIndex->MultiplyPoint(in, out);
    std::copy(out, out + 3, g);
  };
  auto vector = [&](const double w[3], double g[3])
  {
    const double in[4] = { w[0], w[1], w[2], 0.0 };
    double out[4];
    toIndex->MultiplyPoint(in, out);
    std::copy(out, out + 3, g);
  };

  // The plane through the volume's centre (in world) perpendicular to forward.
  double bounds[6], c[3];
  volume->GetBounds(bounds);
  double physical[4] = {
    0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5]), 1.0
  };
  if (propMatrix)
  {
    propMatrix->MultiplyPoint(physical, physical);
  }
  std::copy(physical, physical + 3, c);
  double toPlane[3];
  vtkMath::Subtract(c, this->Position, toPlane);
  const double distance = vtkMath::Dot(toPlane, this->Forward);
  // Offsets of the centre ray's point per pixel: for the formulas of the class comment, a
  // pixel step moves x by 2 / W, which moves the ray's point on that plane by
  // 2 HalfWidth / W right, times the plane's distance under perspective (forward is unit and
  // orthogonal to right and up).
  const double scale = this->Parallel ? 1.0 : distance;
  double base[3], stepX[3], stepY[3];
  for (int r = 0; r < 3; ++r)
  {
    base[r] = this->Position[r] + distance * this->Forward[r];
    stepX[r] = scale * 2.0 * this->HalfWidth / this->ImageSize[0] * this->Right[r];
    stepY[r] = scale * 2.0 * this->HalfHeight / this->ImageSize[1] * this->Up[r];
  }
  point(base, centre);
  vector(stepX, dx);
  vector(stepY, dy);
  vector(this->Forward, forward);
  perspective = !this->Parallel;
  if (perspective)
  {
    point(this->Position, eye);
  }
  else
  {
    vtkMath::Subtract(centre, forward, eye);
  }
  return true;
}

//------------------------------------------------------------------------------
double vtkCameraRayModel::ComputeProjectionMismatch() const
{
  if (!this->Camera)
  {
    return VTK_DOUBLE_MAX;
  }
  const int w = this->ImageSize[0], h = this->ImageSize[1];
  vtkMatrix4x4* m =
    this->Camera->GetCompositeProjectionTransformMatrix(static_cast<double>(w) / h, -1.0, 1.0);
  double range[2];
  this->Camera->GetClippingRange(range);
  double worst = 0.0;
  const int pixels[5][2] = {
    { 0, 0 }, { w - 1, 0 }, { 0, h - 1 }, { w - 1, h - 1 }, { w / 2, h / 2 }
  };
  for (const auto& pixel : pixels)
  {
    double o[3], d[3];
    this->GetPixelRay(pixel[0], pixel[1], o, d);
    const double x = 2.0 * (pixel[0] + 0.5) / w - 1.0, y = 2.0 * (pixel[1] + 0.5) / h - 1.0;
    for (const double s : { range[0], 0.5 * (range[0] + range[1]), range[1] })
    {
      const double p[4] = { o[0] + s * d[0], o[1] + s * d[1], o[2] + s * d[2], 1.0 };
      double q[4];
      m->MultiplyPoint(p, q);
      if (!(q[3] != 0.0))
      {
        return VTK_DOUBLE_MAX;
      }
      worst = std::max({ worst, std::abs(q[0] / q[3] - x), std::abs(q[1] / q[3] - y) });
    }
  }
  return worst;
}

//------------------------------------------------------------------------------
void vtkCameraRayModel::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Camera: " << this->Camera << "\n";
  os << indent << "ImageSize: " << this->ImageSize[0] << " " << this->ImageSize[1] << "\n";
}
