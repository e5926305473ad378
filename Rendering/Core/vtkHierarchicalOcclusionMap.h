// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkHierarchicalOcclusionMap
 * @brief   pyramid of opaque-pixel counts for hidden volume removal
 *
 * The hierarchical occlusion maps of Mora, Jessel and Caubet's object-order ray caster
 * (section 4.2, after Zhang et al.): level 0 is the image, each pixel of level l covers
 * 2^l x 2^l pixels of the image and counts how many of them are opaque. A pixel that becomes
 * opaque increments one count per level (log2 of the image size), and a screen rectangle is
 * hidden when every pixel in it is opaque, which is read from the coarsest level whose pixels
 * are as large as the rectangle and refined only under partly opaque pixels. Unlike the
 * paper's 0..16 counters over overlapping squares, the test is exact: it answers true only
 * when all pixels of the rectangle are opaque. A value class for inner loops (not a
 * vtkObject, not wrapped); not thread-safe, one map per image tile.
 */
#ifndef vtkHierarchicalOcclusionMap_h
#define vtkHierarchicalOcclusionMap_h

#include "hovrRenderingCoreModule.h" // For export macro

#include <vector> // For std::vector

class HOVRRENDERINGCORE_EXPORT vtkHierarchicalOcclusionMap
{
public:
  /**
   * Size the map to width x height pixels (at least 1 x 1), all transparent.
   */
  void Initialize(int width, int height);

  int GetWidth() const { return this->Width; }
  int GetHeight() const { return this->Height; }

  /**
   * Levels of the pyramid: level 0 is the image, the last one has a single pixel.
   */
  int GetNumberOfLevels() const { return static_cast<int>(this->Counts.size()); }

  /**
   * Whether pixel (x, y) of the image is opaque. Indices are not checked.
   */
  bool IsPixelOpaque(int x, int y) const { return this->Counts[0][x + this->Width * y] != 0; }

  /**
   * Mark pixel (x, y) opaque (once; later calls do nothing). Indices are not checked.
   */
  void SetPixelOpaque(int x, int y);

  /**
   * Whether every pixel of [x0, x1] x [y0, y1] (inclusive, clipped to the image) is opaque;
   * true for a rectangle entirely outside the image.
   */
  bool IsRectangleOpaque(int x0, int y0, int x1, int y1) const;

  /**
   * Number of opaque pixels.
   */
  int GetNumberOfOpaquePixels() const { return this->Counts.empty() ? 0 : this->Counts.back()[0]; }

private:
  // Pixels of the image in pixel (px, py) of a level, at the image's border too.
  int Area(int level, int px, int py) const;
  bool IsOpaque(int level, int px, int py, int x0, int y0, int x1, int y1) const;

  int Width = 0;
  int Height = 0;
  std::vector<int> LevelWidths;
  std::vector<int> LevelHeights;
  std::vector<std::vector<int>> Counts;
};

#endif
