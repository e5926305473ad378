// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkVolumeBrickLayout: the fewest bricks within the texture limits (an axis beyond the
// GPU's 3D texture size, a byte limit, ghosts), every cell owned by exactly one brick, texture
// extents of owned cells plus ghosts clamped to the volume, and a back-to-front order that
// every ray, from eyes inside and outside the volume and for parallel rays, meets in reverse.
#include "vtkIdList.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"
#include "vtkVolumeBrickLayout.h"

#include "hovrTestUtilities.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace
{
hovrTest::Checker check;

std::string Text(const int v[3])
{
  return std::to_string(v[0]) + " x " + std::to_string(v[1]) + " x " + std::to_string(v[2]);
}

// Every cell in exactly one brick's owned cells; texture points = owned +- ghosts, clamped,
// within the limits.
void CheckPartition(vtkVolumeBrickLayout* layout, const std::string& what)
{
  const int* dims = layout->GetDimensions();
  const int g = layout->GetGhostPoints();
  std::vector<int> owners(static_cast<size_t>(dims[0] - 1) * (dims[1] - 1) * (dims[2] - 1), 0);
  bool extents = true, limits = true;
  for (int b = 0; b < layout->GetNumberOfBricks(); ++b)
  {
    int cells[6], points[6], size[3];
    layout->GetBrickCells(b, cells);
    layout->GetBrickPoints(b, points);
    layout->GetBrickSize(b, size);
    double bytes = layout->GetBytesPerPoint();
    for (int a = 0; a < 3; ++a)
    {
      extents = extents && cells[2 * a] < cells[2 * a + 1] &&
        points[2 * a] == std::max(cells[2 * a] - g, 0) &&
        points[2 * a + 1] == std::min(cells[2 * a + 1] + g, dims[a] - 1) &&
        size[a] == points[2 * a + 1] - points[2 * a] + 1;
      limits = limits && size[a] <= layout->GetMaximumBrickPoints();
      bytes *= size[a];
    }
    limits = limits && bytes <= layout->GetMaximumBrickBytes();
    for (int k = cells[4]; k < cells[5]; ++k)
    {
      for (int j = cells[2]; j < cells[3]; ++j)
      {
        for (int i = cells[0]; i < cells[1]; ++i)
        {
          ++owners[i + static_cast<size_t>(dims[0] - 1) * (j + static_cast<size_t>(dims[1] - 1) * k)];
        }
      }
    }
  }
  check(std::all_of(owners.begin(), owners.end(), [](int n) { return n == 1; }),
    what + ": every cell belongs to exactly one brick");
  check(extents, what + ": texture points are the owned cells' points plus the ghosts, clamped");
  check(limits, what + ": every brick within the point and byte limits");
}

// The brick holding point p (0-based grid index), -1 outside.
int BrickAt(vtkVolumeBrickLayout* layout, const double p[3])
{
  for (int b = 0; b < layout->GetNumberOfBricks(); ++b)
  {
    int cells[6];
    layout->GetBrickCells(b, cells);
    bool inside = true;
    for (int a = 0; a < 3; ++a)
    {
      inside = inside && p[a] >= cells[2 * a] && p[a] < cells[2 * a + 1];
    }
    if (inside)
    {
      return b;
    }
  }
  return -1;
}

// Random rays (from eye, or parallel along dir): the bricks they visit come in decreasing
// position in the drawing order.
bool RaysMeetOrderReversed(vtkVolumeBrickLayout* layout, const double eye[3], bool parallel,
  const double dir[3], vtkMinimalStandardRandomSequence* random)
{
  vtkNew<vtkIdList> order;
  layout->GetBackToFront(parallel ? dir : eye, parallel, order);
  std::vector<int> position(static_cast<size_t>(layout->GetNumberOfBricks()));
  for (vtkIdType n = 0; n < order->GetNumberOfIds(); ++n)
  {
    position[order->GetId(n)] = static_cast<int>(n);
  }
  const int* dims = layout->GetDimensions();
  for (int r = 0; r < 100; ++r)
  {
    double o[3], v[3];
    for (int a = 0; a < 3; ++a)
    {
      random->Next();
      if (parallel)
      {
        o[a] = random->GetRangeValue(-0.5, dims[a] - 0.5) - 4.0 * dims[a] * dir[a];
        v[a] = dir[a];
      }
      else
      {
        o[a] = eye[a];
        v[a] = random->GetRangeValue(-1.0, 1.0);
      }
    }
    const double length = 4.0 * (dims[0] + dims[1] + dims[2]);
    int last = -1;
    for (double t = 0.0; t < length; t += 0.1)
    {
      const double p[3] = { o[0] + t * v[0], o[1] + t * v[1], o[2] + t * v[2] };
      const int b = BrickAt(layout, p);
      if (b >= 0 && b != last)
      {
        if (last >= 0 && position[b] >= position[last])
        {
          return false;
        }
        last = b;
      }
    }
  }
  return true;
}
}

int TestVolumeBrickLayout(int, char*[])
{
  hovrTest::MessageCapture messages;
  vtkNew<vtkVolumeBrickLayout> layout;
  check(layout->GetGhostPoints() == 0 && layout->GetMaximumBrickPoints() == 2048 &&
      layout->GetMaximumBrickBytes() == 1073741824.0 && layout->GetBytesPerPoint() == 4,
    "defaults: no ghosts, 2048 points, 1 GiB, 4 bytes a point");

  // An axis of 4096 points past a 2048-point texture limit: 3 pieces (2 would need 2049).
  layout->SetDimensions(4096, 32, 32);
  check(layout->Update() && layout->GetNumberOfBricks() == 3, "4096 x 32 x 32: 3 bricks");
  CheckPartition(layout, "4096 x 32 x 32");
  layout->SetGhostPoints(3);
  check(layout->Update() && layout->GetNumberOfBricks() == 3, "with 3 ghosts: still 3 bricks");
  CheckPartition(layout, "4096 x 32 x 32, 3 ghosts");

  // 256^3 in forced 64-cell bricks: 65 points a side.
  layout->SetDimensions(256, 256, 256);
  layout->SetGhostPoints(0);
  layout->SetMaximumBrickPoints(65);
  int pieces[3];
  check(layout->Update(), "256^3, 65 points");
  layout->GetNumberOfPieces(pieces);
  check(layout->GetNumberOfBricks() == 64 && pieces[0] == 4 && pieces[1] == 4 && pieces[2] == 4,
    "256^3 in 65-point bricks: 4 x 4 x 4, got " + Text(pieces));
  CheckPartition(layout, "256^3, 65 points");
  layout->SetGhostPoints(2);
  check(layout->Update(), "256^3, 65 points, 2 ghosts");
  layout->GetNumberOfPieces(pieces);
  check(pieces[0] == 5 && pieces[1] == 5 && pieces[2] == 5,
    "2 ghosts a side leave 60 cells a brick: 5 pieces an axis, got " + Text(pieces));
  CheckPartition(layout, "256^3, 65 points, 2 ghosts");

  // A byte limit: 512^3 float in at most 128 MiB bricks, split along the largest axis first.
  layout->SetDimensions(512, 512, 512);
  layout->SetGhostPoints(0);
  layout->SetMaximumBrickPoints(2048);
  layout->SetMaximumBrickBytes(128.0 * 1048576.0);
  check(layout->Update(), "512^3 float in 128 MiB");
  layout->GetNumberOfPieces(pieces);
  check(layout->GetNumberOfBricks() == 8, "512^3 float in 128 MiB: 8 bricks, got " + Text(pieces));
  CheckPartition(layout, "512^3 float in 128 MiB");
  layout->SetMaximumBrickBytes(1073741824.0);
  check(layout->Update() && layout->GetNumberOfBricks() == 1, "512^3 float in 1 GiB: one brick");

  // Visibility order: eyes outside, inside, on a cut, and parallel rays, on an uneven grid.
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(11);
  layout->SetDimensions(40, 23, 31);
  layout->SetMaximumBrickPoints(11);
  check(layout->Update(), "40 x 23 x 31 in 11-point bricks");
  layout->GetNumberOfPieces(pieces);
  CheckPartition(layout, "40 x 23 x 31");
  const double eyes[][3] = { { -30, 50, 80 }, { 17.3, 9.1, 12.7 }, { 20, 11.5, -4 },
    { 0.5, 0.5, 0.5 }, { 39, 22, 30 } };
  for (const double* eye : eyes)
  {
    check(RaysMeetOrderReversed(layout, eye, false, eye, random),
      "rays from (" + std::to_string(eye[0]) + ", " + std::to_string(eye[1]) + ", " +
        std::to_string(eye[2]) + ") meet the bricks in reverse drawing order");
  }
  const double directions[][3] = { { 1, 0.3, -0.2 }, { -0.4, 1, 0 }, { 0, 0, -1 },
    { -1, -1, 1 } };
  for (const double* dir : directions)
  {
    check(RaysMeetOrderReversed(layout, dir, true, dir, random),
      "parallel rays along (" + std::to_string(dir[0]) + ", " + std::to_string(dir[1]) + ", " +
        std::to_string(dir[2]) + ") meet the bricks in reverse drawing order");
  }
  messages.ExpectNone(check, "for valid layouts");

  // Impossible limits: errors, no bricks.
  layout->SetDimensions(100, 100, 100);
  layout->SetMaximumBrickPoints(5);
  layout->SetGhostPoints(2);
  check(!layout->Update() && layout->GetNumberOfBricks() == 0 && messages.TakeError("ghost"),
    "one cell and 2 ghosts a side in 5 points: an error, no bricks");
  layout->SetGhostPoints(0);
  layout->SetMaximumBrickPoints(2048);
  layout->SetMaximumBrickBytes(4.0);
  check(!layout->Update() && layout->GetNumberOfBricks() == 0 && messages.TakeError("bytes"),
    "a byte limit below one cell's points: an error, no bricks");
  layout->SetDimensions(1, 10, 10);
  layout->SetMaximumBrickBytes(1e9);
  check(!layout->Update() && messages.TakeError("at least 2 points"),
    "a volume one point thick: an error");
  messages.ExpectNone(check, "at the end of the test");
  return check.Result("TestVolumeBrickLayout");
}
