// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkHierarchicalOcclusionMap: on an odd-sized map (37 x 23, so every level has truncated
// border pixels) filled in random order with opaque pixels and blobs, IsRectangleOpaque
// agrees with a brute-force scan for thousands of random rectangles (partly outside the
// image too) at every fill stage; level count and opaque-pixel count.
#include "vtkHierarchicalOcclusionMap.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"

#include "hovrTestUtilities.h"

#include <string>
#include <vector>

int TestHierarchicalOcclusionMap(int, char*[])
{
  hovrTest::Checker check;
  const int w = 37, h = 23;
  vtkHierarchicalOcclusionMap map;
  map.Initialize(w, h);
  check(map.GetNumberOfLevels() == 7, "37 x 23 has levels up to 1 x 1: 7 levels");
  check(map.GetNumberOfOpaquePixels() == 0 && map.IsRectangleOpaque(40, 0, 50, 5) &&
      !map.IsRectangleOpaque(0, 0, 0, 0),
    "empty map: nothing inside is opaque, rectangles outside are");
  std::vector<char> opaque(w * h, 0);
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(3);
  auto next = [&](int n)
  {
    random->Next();
    return static_cast<int>(random->GetValue() * n);
  };
  int mismatches = 0, tested = 0, opaqueAnswers = 0;
  for (int stage = 0; stage < 12; ++stage)
  {
    // Blobs (so that large rectangles become opaque) and single pixels.
    for (int b = 0; b < 3; ++b)
    {
      const int x0 = next(w), y0 = next(h), bw = 1 + next(12), bh = 1 + next(8);
      for (int y = y0; y < std::min(h, y0 + bh); ++y)
      {
        for (int x = x0; x < std::min(w, x0 + bw); ++x)
        {
          map.SetPixelOpaque(x, y);
          opaque[x + w * y] = 1;
        }
      }
    }
    for (int p = 0; p < 20; ++p)
    {
      const int x = next(w), y = next(h);
      map.SetPixelOpaque(x, y);
      map.SetPixelOpaque(x, y); // twice: counted once
      opaque[x + w * y] = 1;
    }
    for (int r = 0; r < 500; ++r)
    {
      const int x0 = next(w + 10) - 5, y0 = next(h + 10) - 5;
      const int x1 = x0 + next(16), y1 = y0 + next(10);
      bool expected = true;
      for (int y = std::max(y0, 0); y <= std::min(y1, h - 1); ++y)
      {
        for (int x = std::max(x0, 0); x <= std::min(x1, w - 1); ++x)
        {
          expected = expected && opaque[x + w * y];
        }
      }
      const bool got = map.IsRectangleOpaque(x0, y0, x1, y1);
      mismatches += got != expected ? 1 : 0;
      opaqueAnswers += got ? 1 : 0;
      ++tested;
    }
  }
  check(mismatches == 0,
    std::to_string(mismatches) + " of " + std::to_string(tested) + " rectangles answered wrong");
  check(opaqueAnswers > 200 && opaqueAnswers < tested - 200,
    "both answers occur (" + std::to_string(opaqueAnswers) + " opaque)");
  int count = 0;
  for (char o : opaque)
  {
    count += o;
  }
  check(map.GetNumberOfOpaquePixels() == count, "opaque pixels counted once each");
  map.Initialize(w, h);
  check(map.GetNumberOfOpaquePixels() == 0 && !map.IsPixelOpaque(0, 0), "Initialize clears");
  return check.Result("TestHierarchicalOcclusionMap");
}
