// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkCameraRayModel: pixel rays against (a) hand-computed rays of the documented formulas and
// (b) VTK's own projection of the same vtkCamera: every point of the ray of pixel (i, j) must
// project to that pixel's centre in normalised device coordinates. Bad cameras give errors.
#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkTransform.h"

#include "hovrTestUtilities.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace
{
hovrTest::Checker check;

// Largest distance, in normalised device coordinates, between the projection of points along
// each pixel ray (by the camera's own composite projection) and the pixel centre.
double ProjectionMismatch(vtkCamera* camera, vtkCameraRayModel* model, int w, int h)
{
  const double aspect = static_cast<double>(w) / h;
  vtkMatrix4x4* m = camera->GetCompositeProjectionTransformMatrix(aspect, -1.0, 1.0);
  double worst = 0.0;
  for (int j = 0; j < h; ++j)
  {
    for (int i = 0; i < w; ++i)
    {
      double o[3], d[3];
      model->GetPixelRay(i, j, o, d);
      const double x = 2.0 * (i + 0.5) / w - 1.0, y = 2.0 * (j + 0.5) / h - 1.0;
      for (double s : { 0.5, 3.0, 10.0 })
      {
        const double p[4] = { o[0] + s * d[0], o[1] + s * d[1], o[2] + s * d[2], 1.0 };
        double q[4];
        m->MultiplyPoint(p, q);
        worst = std::max({ worst, std::abs(q[0] / q[3] - x), std::abs(q[1] / q[3] - y) });
      }
      worst = std::max(worst, std::abs(vtkMath::Norm(d) - 1.0));
    }
  }
  return worst;
}

// Distance from point p to the line through o along the unit vector d.
double DistanceToRay(const double p[3], const double o[3], const double d[3])
{
  double op[3], c[3];
  vtkMath::Subtract(p, o, op);
  vtkMath::Cross(op, d, c);
  return vtkMath::Norm(c);
}

std::string Ray(const double o[3], const double d[3])
{
  std::ostringstream os;
  os << "origin (" << o[0] << ", " << o[1] << ", " << o[2] << "), direction (" << d[0] << ", "
     << d[1] << ", " << d[2] << ")";
  return os.str();
}
}

int TestCameraRayModel(int, char*[])
{
  hovrTest::MessageCapture messages;
  vtkNew<vtkCamera> camera;
  vtkNew<vtkCameraRayModel> model;
  model->SetCamera(camera);

  //----------------------------------------------------------------------------
  // Hand-computed rays: camera at (0, 0, 5) looking at the origin, view up +y, so
  // forward = (0, 0, -1), right = (1, 0, 0), up = (0, 1, 0); image 4 x 2.
  camera->SetPosition(0, 0, 5);
  camera->SetFocalPoint(0, 0, 0);
  camera->SetViewUp(0, 1, 0);
  model->SetImageSize(4, 2);
  {
    // Parallel, scale 2: pixel (0, 0) has x = 2 (0.5) / 4 - 1 = -0.75, y = 2 (0.5) / 2 - 1 =
    // -0.5, so origin = (0, 0, 5) + (-0.75)(2)(4/2) right + (-0.5)(2) up = (-3, -1, 5).
    camera->ParallelProjectionOn();
    camera->SetParallelScale(2.0);
    check(model->Prepare(), "Prepare a parallel camera");
    double o[3], d[3];
    model->GetPixelRay(0, 0, o, d);
    check(o[0] == -3.0 && o[1] == -1.0 && o[2] == 5.0 && d[0] == 0.0 && d[1] == 0.0 && d[2] == -1.0,
      "parallel pixel (0, 0): expected origin (-3, -1, 5), direction (0, 0, -1), got " + Ray(o, d));
    // Pixel (3, 1): x = 0.75, y = 0.5: origin (3, 1, 5).
    model->GetPixelRay(3, 1, o, d);
    check(o[0] == 3.0 && o[1] == 1.0 && o[2] == 5.0,
      "parallel pixel (3, 1): expected origin (3, 1, 5), got " + Ray(o, d));

    // Perspective, view angle 90 degrees (t = tan 45 = 1): pixel (3, 1) has direction
    // normalize(forward + 0.75 (1)(2) right + 0.5 (1) up) = (1.5, 0.5, -1) / sqrt(3.5).
    camera->ParallelProjectionOff();
    camera->SetViewAngle(90.0);
    check(model->Prepare(), "Prepare a perspective camera");
    model->GetPixelRay(3, 1, o, d);
    const double n = std::sqrt(3.5);
    const double expected[3] = { 1.5 / n, 0.5 / n, -1.0 / n };
    check(o[0] == 0.0 && o[1] == 0.0 && o[2] == 5.0,
      "perspective rays start at the eye, got " + Ray(o, d));
    check(std::abs(d[0] - expected[0]) < 1e-15 && std::abs(d[1] - expected[1]) < 1e-15 &&
        std::abs(d[2] - expected[2]) < 1e-15,
      "perspective pixel (3, 1): expected direction (1.5, 0.5, -1) / sqrt(3.5), got " + Ray(o, d));
  }

  //----------------------------------------------------------------------------
  // A general camera (oblique, rolled view up, not orthogonal to the view direction), odd
  // non-square image: every pixel ray projects onto its pixel centre through VTK's own
  // projection. The matrices are built in double from the same settings, so the projections
  // agree to rounding: 1e-12 in normalised device coordinates (pixel size ~0.1-0.3 here).
  const int w = 7, h = 5;
  model->SetImageSize(w, h);
  camera->SetPosition(4.0, -3.0, 2.5);
  camera->SetFocalPoint(0.5, 0.25, -0.75);
  camera->SetViewUp(0.3, 0.2, 1.0);
  const double projectionTolerance = 1e-12;
  for (int parallel : { 1, 0 })
  {
    const char* kind = parallel ? "parallel" : "perspective";
    camera->SetParallelProjection(parallel);
    camera->SetParallelScale(1.7);
    camera->SetViewAngle(35.0);
    check(model->Prepare(), std::string("Prepare the oblique ") + kind + " camera");
    check.Near(ProjectionMismatch(camera, model, w, h),
      0.0,
      projectionTolerance,
      std::string(kind) + ": pixel rays project onto their pixel centres");

    // The centre pixel ray (x = y = 0) passes through the focal point, along the view
    // direction, for both projections.
    double o[3], d[3], focal[3], dop[3];
    camera->GetFocalPoint(focal);
    camera->GetDirectionOfProjection(dop);
    model->GetPixelRay(w / 2, h / 2, o, d);
    check.Near(DistanceToRay(focal, o, d),
      0.0,
      1e-12,
      std::string(kind) + ": the centre pixel ray hits the focal point");
    check.Near(vtkMath::Distance2BetweenPoints(d, dop),
      0.0,
      1e-24,
      std::string(kind) + ": the centre pixel ray runs along the direction of projection");
    double ro[3], rd[3];
    model->GetRay(0.0, 0.0, ro, rd);
    check(
      std::equal(o, o + 3, ro) && std::equal(d, d + 3, rd), "GetRay(0, 0) is the centre pixel ray");

    // Every parallel ray has the direction of projection and starts in the plane through the
    // camera position; every perspective ray starts at the eye.
    double position[3];
    camera->GetPosition(position);
    double worstDirection = 0.0, worstOrigin = 0.0;
    for (int j = 0; j < h; ++j)
    {
      for (int i = 0; i < w; ++i)
      {
        model->GetPixelRay(i, j, o, d);
        double offset[3];
        vtkMath::Subtract(o, position, offset);
        if (parallel)
        {
          worstDirection =
            std::max(worstDirection, std::sqrt(vtkMath::Distance2BetweenPoints(d, dop)));
          worstOrigin = std::max(worstOrigin, std::abs(vtkMath::Dot(offset, dop)));
        }
        else
        {
          worstOrigin = std::max(worstOrigin, vtkMath::Norm(offset));
        }
      }
    }
    check.Near(
      worstDirection, 0.0, 1e-15, std::string(kind) + ": parallel rays share the view direction");
    check.Near(worstOrigin,
      0.0,
      1e-14,
      std::string(kind) + ": ray origins on the camera plane / at the eye");
  }

  // vtkCamera's horizontal view angle convention (perspective; the parallel scale stays
  // vertical in VTK whatever the flag says).
  camera->UseHorizontalViewAngleOn();
  for (int parallel : { 0, 1 })
  {
    camera->SetParallelProjection(parallel);
    check(model->Prepare(), "Prepare with a horizontal view angle");
    check.Near(ProjectionMismatch(camera, model, w, h),
      0.0,
      projectionTolerance,
      std::string(parallel ? "parallel" : "perspective") +
        ", horizontal view angle: pixel rays project onto their pixel centres");
  }
  camera->UseHorizontalViewAngleOff();
  camera->ParallelProjectionOff();

  //----------------------------------------------------------------------------
  // The grid ray frame (what vtkAnalyticVolumeMapper gives its shader): for every pixel, the
  // frame's base point lies on that pixel's ray, mapped to the grid index of a volume with an
  // extent not starting at 0, anisotropic spacing, an origin and a rotated, scaled prop; the
  // base point lies on the plane through the volume's centre facing the camera, and the
  // frame's direction is the ray's. ComputeProjectionMismatch is ~0 for cameras the model
  // describes and large for a window centre.
  {
    vtkNew<vtkImageData> volume;
    volume->SetExtent(2, 9, -3, 4, 5, 10);
    volume->SetSpacing(0.5, 0.25, 0.75);
    volume->SetOrigin(-1.0, 0.5, -4.0);
    vtkNew<vtkTransform> prop;
    prop->Translate(0.3, -0.2, 0.1);
    prop->RotateWXYZ(20.0, 1.0, 2.0, 0.5);
    prop->Scale(1.1, 0.9, 1.0);
    vtkMatrix4x4* propMatrix = prop->GetMatrix();
    vtkNew<vtkMatrix4x4> worldToIndex;
    vtkMatrix4x4::Invert(propMatrix, worldToIndex);
    vtkMatrix4x4::Multiply4x4(volume->GetPhysicalToIndexMatrix(), worldToIndex, worldToIndex);
    double physicalCentre[4] = { 0, 0, 0, 1 }, worldCentre[4];
    volume->GetCenter(physicalCentre);
    propMatrix->MultiplyPoint(physicalCentre, worldCentre);
    for (int parallel : { 1, 0 })
    {
      const std::string kind = parallel ? "parallel" : "perspective";
      camera->SetParallelProjection(parallel);
      check(model->Prepare(), "Prepare for the grid frame");
      check(model->ComputeProjectionMismatch() < 1e-12,
        kind + ": no projection mismatch for a camera the model describes");
      double centre[3], dx[3], dy[3], eye[3], forward[3];
      bool perspective = false;
      check(model->GetGridRayFrame(volume, propMatrix, centre, dx, dy, eye, forward, perspective) &&
          perspective == !parallel,
        kind + ": grid ray frame");
      double worstLine = 0.0, worstDirection = 0.0, worstPlane = 0.0;
      for (int j = 0; j < h; ++j)
      {
        for (int i = 0; i < w; ++i)
        {
          double base[3], direction[3], o[3], d[3];
          for (int a = 0; a < 3; ++a)
          {
            base[a] = centre[a] + (i + 0.5 - 0.5 * w) * dx[a] + (j + 0.5 - 0.5 * h) * dy[a];
            direction[a] = perspective ? base[a] - eye[a] : forward[a];
          }
          vtkMath::Normalize(direction);
          // The model's world ray in grid index (0-based from the extent's first point).
          model->GetPixelRay(i, j, o, d);
          double oi[4] = { o[0], o[1], o[2], 1.0 }, di[4] = { d[0], d[1], d[2], 0.0 };
          worldToIndex->MultiplyPoint(oi, oi);
          worldToIndex->MultiplyPoint(di, di);
          const int* extent = volume->GetExtent();
          for (int a = 0; a < 3; ++a)
          {
            oi[a] -= extent[2 * a];
          }
          vtkMath::Normalize(di);
          worstLine = std::max(worstLine, DistanceToRay(base, oi, di));
          worstDirection =
            std::max(worstDirection, std::sqrt(vtkMath::Distance2BetweenPoints(direction, di)));
          // Back in world: base - world centre is orthogonal to the view direction.
          double bw[4] = { base[0] + extent[0], base[1] + extent[2], base[2] + extent[4], 1.0 };
          volume->TransformContinuousIndexToPhysicalPoint(bw, bw);
          propMatrix->MultiplyPoint(bw, bw);
          double offset[3], dop[3];
          vtkMath::Subtract(bw, worldCentre, offset);
          camera->GetDirectionOfProjection(dop);
          worstPlane = std::max(worstPlane, std::abs(vtkMath::Dot(offset, dop)));
        }
      }
      check.Near(worstLine, 0.0, 1e-12, kind + ": frame base points lie on the pixel rays");
      check.Near(worstDirection, 0.0, 1e-12, kind + ": frame directions are the pixel rays'");
      check.Near(worstPlane, 0.0, 1e-12, kind + ": base points on the plane through the centre");
    }
    vtkNew<vtkMatrix4x4> singular;
    singular->SetElement(2, 2, 0.0);
    double v[5][3];
    bool perspective;
    check(!model->GetGridRayFrame(volume, singular, v[0], v[1], v[2], v[3], v[4], perspective),
      "a singular prop matrix has no grid frame");
    camera->SetWindowCenter(1e-6, 0.0);
    check(
      model->ComputeProjectionMismatch() > 1e-7, "a window centre shows as a projection mismatch");
    camera->SetWindowCenter(0.0, 0.0);
  }
  camera->ParallelProjectionOff();

  // The model follows camera changes through its MTime.
  const vtkMTimeType before = model->GetMTime();
  camera->Azimuth(10.0);
  check(model->GetMTime() > before, "camera changes modify the ray model's MTime");
  check(model->Prepare(), "Prepare after Azimuth");
  check.Near(ProjectionMismatch(camera, model, w, h),
    0.0,
    projectionTolerance,
    "after Azimuth: pixel rays project onto their pixel centres");
  messages.ExpectNone(check, "for valid cameras");

  //----------------------------------------------------------------------------
  // Bad cameras and sizes: Prepare() fails with an error.
  {
    vtkNew<vtkCameraRayModel> bad;
    check(!bad->Prepare() && messages.TakeError("No camera"), "missing camera is an error");
    vtkNew<vtkCamera> cam;
    bad->SetCamera(cam);
    cam->SetPosition(1, 2, 3);
    cam->SetFocalPoint(1, 2, 3);
    check(
      !bad->Prepare() && messages.TakeError("focal point"), "position == focal point is an error");
    cam->SetFocalPoint(1, 2, -3);
    cam->SetViewUp(0, 0, 1);
    check(!bad->Prepare() && messages.TakeError("parallel"),
      "view up parallel to the view direction is an error");
    cam->SetViewUp(0, 1, 0);
    check(bad->Prepare(), "valid again with a proper view up");
    messages.Take();
    for (const auto& size : { std::make_pair(0, 10), std::make_pair(10, 0), std::make_pair(-3, 4) })
    {
      bad->SetImageSize(size.first, size.second);
      check(!bad->Prepare() && messages.TakeError("image size"),
        "image size " + std::to_string(size.first) + " x " + std::to_string(size.second) +
          " is an error");
    }
    bad->SetImageSize(10, 10);
    cam->ParallelProjectionOn();
    for (double scale : { 0.0, -1.0 })
    {
      cam->SetParallelScale(scale);
      check(!bad->Prepare() && messages.TakeError("parallel scale"),
        "parallel scale " + std::to_string(scale) + " is an error");
    }
    cam->SetParallelScale(1.0);
    check(bad->Prepare(), "valid again with a positive parallel scale");
  }
  messages.ExpectNone(check, "at the end of the test");
  return check.Result("TestCameraRayModel");
}
