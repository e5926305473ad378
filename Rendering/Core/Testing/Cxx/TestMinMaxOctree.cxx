// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkMinMaxOctree: every node's range against a brute-force scan of its points (odd grid
// sizes, so the last nodes are truncated; values that floats cannot hold exactly, so ranges
// must be rounded outwards; NaN points ignored, NaN-only nodes empty); level sizes; a grid of
// one cell; bad input.
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkMinMaxOctree.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkUnsignedCharArray.h"

#include "hovrTestUtilities.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

int TestMinMaxOctree(int, char*[])
{
  hovrTest::Checker check;
  hovrTest::MessageCapture messages;
  vtkNew<vtkMinMaxOctree> octree;

  // 14 x 8 x 11 points: 13 x 7 x 10 cells, so levels of 7x4x5, 4x2x3, 2x1x2, 1x1x1 nodes.
  const int dims[3] = { 14, 8, 11 };
  const vtkIdType n = static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2];
  vtkNew<vtkDoubleArray> values;
  values->SetNumberOfTuples(n);
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(7);
  for (vtkIdType p = 0; p < n; ++p)
  {
    random->Next();
    values->SetValue(p, 100.0 * random->GetValue() + 1e-9); // not a float
  }
  // A corner block of NaN: the level-1 node (0, 0, 0) covers points 0..2 on each axis.
  for (int k = 0; k <= 2; ++k)
  {
    for (int j = 0; j <= 2; ++j)
    {
      for (int i = 0; i <= 2; ++i)
      {
        values->SetValue(i + dims[0] * (j + dims[1] * k), std::nan(""));
      }
    }
  }
  values->SetValue(5 + dims[0] * (3 + dims[1] * 4), std::nan("")); // a lone NaN
  check(octree->Build(values, dims), "build over a 14 x 8 x 11 grid");
  check(octree->GetNumberOfLevels() == 4, "4 levels above the cells");
  const int expected[5][3] = { { 13, 7, 10 }, { 7, 4, 5 }, { 4, 2, 3 }, { 2, 1, 2 }, { 1, 1, 1 } };
  for (int level = 0; level <= 4; ++level)
  {
    int size[3];
    octree->GetLevelSize(level, size);
    check(std::equal(size, size + 3, expected[level]),
      "level " + std::to_string(level) + " size " + std::to_string(size[0]) + " x " +
        std::to_string(size[1]) + " x " + std::to_string(size[2]));
  }
  int outside[3];
  octree->GetLevelSize(5, outside);
  check(outside[0] == 0 && outside[1] == 0 && outside[2] == 0, "no level 5");

  int wrong = 0, notContaining = 0, emptyNodes = 0;
  for (int level = 1; level <= 4; ++level)
  {
    const int side = 1 << level;
    for (int k = 0; k < expected[level][2]; ++k)
    {
      for (int j = 0; j < expected[level][1]; ++j)
      {
        for (int i = 0; i < expected[level][0]; ++i)
        {
          double lo = std::numeric_limits<double>::infinity(), hi = -lo;
          for (int pk = k * side; pk <= std::min((k + 1) * side, dims[2] - 1); ++pk)
          {
            for (int pj = j * side; pj <= std::min((j + 1) * side, dims[1] - 1); ++pj)
            {
              for (int pi = i * side; pi <= std::min((i + 1) * side, dims[0] - 1); ++pi)
              {
                const double v = values->GetValue(pi + dims[0] * (pj + dims[1] * pk));
                if (!std::isnan(v))
                {
                  lo = std::min(lo, v);
                  hi = std::max(hi, v);
                }
              }
            }
          }
          float range[2];
          octree->GetNodeRange(level, i, j, k, range);
          if (!(lo <= hi))
          {
            emptyNodes += range[0] > range[1] ? 1 : 0;
            wrong += range[0] > range[1] ? 0 : 1;
            continue;
          }
          // Outward rounding: the float range contains the data range and is the tightest.
          notContaining += (range[0] <= lo && range[1] >= hi) ? 0 : 1;
          wrong += (range[0] == std::nextafter(static_cast<float>(lo), -1e30f) ||
                     static_cast<double>(range[0]) == lo || range[0] == static_cast<float>(lo)) &&
              (range[1] == std::nextafter(static_cast<float>(hi), 1e30f) ||
                range[1] == static_cast<float>(hi))
            ? 0
            : 1;
        }
      }
    }
  }
  check(
    notContaining == 0, std::to_string(notContaining) + " node ranges do not contain their data");
  check(wrong == 0, std::to_string(wrong) + " node ranges are not the rounded data range");
  check(emptyNodes == 1, "the NaN-only node has an empty range");
  check(
    octree->GetMemorySize() == static_cast<vtkIdType>(8 * (7 * 4 * 5 + 4 * 2 * 3 + 2 * 1 * 2 + 1)),
    "8 bytes per node");

  // One cell: no stored level; integer data through the image overload.
  vtkNew<vtkImageData> cube;
  cube->SetDimensions(2, 2, 2);
  cube->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  check(octree->Build(cube) && octree->GetNumberOfLevels() == 0, "a single cell has no level");
  const int builds = octree->GetBuildCount();

  // Bad input: errors, an empty octree.
  const int flat[3] = { 5, 1, 5 };
  vtkNew<vtkUnsignedCharArray> few;
  few->SetNumberOfTuples(25);
  check(!octree->Build(few, flat) && messages.TakeError("2 points"), "a flat grid is an error");
  const int cube5[3] = { 5, 5, 5 };
  check(
    !octree->Build(values, cube5) && messages.TakeError("tuples"), "a size mismatch is an error");
  check(
    !octree->Build(nullptr, dims) && messages.TakeError("No scalars"), "no scalars is an error");
  vtkNew<vtkDoubleArray> vectors;
  vectors->SetNumberOfComponents(3);
  vectors->SetNumberOfTuples(n);
  check(!octree->Build(vectors, dims) && messages.TakeError("single-component"),
    "vectors are an error");
  check(octree->GetNumberOfLevels() == 0 && octree->GetBuildCount() == builds,
    "failed builds leave an empty octree");
  messages.ExpectNone(check, "at the end");
  return check.Result("TestMinMaxOctree");
}
