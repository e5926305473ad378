// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkHierarchicalOcclusionMap.h"

#include <algorithm>

//------------------------------------------------------------------------------
void vtkHierarchicalOcclusionMap::Initialize(int width, int height)
{
  this->Width = std::max(width, 1);
  this->Height = std::max(height, 1);
  this->LevelWidths.clear();
  this->LevelHeights.clear();
  this->Counts.clear();
  int w = this->Width, h = this->Height;
  for (;;)
  {
    this->LevelWidths.push_back(w);
    this->LevelHeights.push_back(h);
    this->Counts.emplace_back(static_cast<size_t>(w) * h, 0);
    if (w == 1 && h == 1)
    {
      break;
    }
    w = (w + 1) / 2;
    h = (h + 1) / 2;
  }
}

//------------------------------------------------------------------------------
int vtkHierarchicalOcclusionMap::Area(int level, int px, int py) const
{
  const int w = std::min((px + 1) << level, this->Width) - (px << level);
  const int h = std::min((py + 1) << level, this->Height) - (py << level);
  return w * h;
}

//------------------------------------------------------------------------------
void vtkHierarchicalOcclusionMap::SetPixelOpaque(int x, int y)
{
  if (this->Counts[0][x + this->Width * y] != 0)
  {
    return;
  }
  for (size_t l = 0; l < this->Counts.size(); ++l)
  {
    ++this->Counts[l][(x >> l) + this->LevelWidths[l] * (y >> l)];
  }
}

//------------------------------------------------------------------------------
bool vtkHierarchicalOcclusionMap::IsOpaque(int level,
  int px,
  int py,
  int x0,
  int y0,
  int x1,
  int y1) const
{
  const int count = this->Counts[level][px + this->LevelWidths[level] * py];
  if (count == this->Area(level, px, py))
  {
    return true;
  }
  if (count == 0 || level == 0)
  {
    return false;
  }
  // Partly opaque: the children that overlap the rectangle decide.
  const int c = level - 1;
  const int cx0 = std::max(px * 2, x0 >> c), cx1 = std::min(px * 2 + 1, x1 >> c);
  const int cy0 = std::max(py * 2, y0 >> c), cy1 = std::min(py * 2 + 1, y1 >> c);
  for (int cy = cy0; cy <= cy1; ++cy)
  {
    for (int cx = cx0; cx <= cx1; ++cx)
    {
      if (!this->IsOpaque(c, cx, cy, x0, y0, x1, y1))
      {
        return false;
      }
    }
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkHierarchicalOcclusionMap::IsRectangleOpaque(int x0, int y0, int x1, int y1) const
{
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, this->Width - 1);
  y1 = std::min(y1, this->Height - 1);
  if (x0 > x1 || y0 > y1)
  {
    return true;
  }
  // The coarsest level at which the rectangle spans at most 2 x 2 pixels.
  int level = 0;
  while (level + 1 < this->GetNumberOfLevels() &&
    ((x1 >> level) - (x0 >> level) > 1 || (y1 >> level) - (y0 >> level) > 1))
  {
    ++level;
  }
  for (int py = y0 >> level; py <= (y1 >> level); ++py)
  {
    for (int px = x0 >> level; px <= (x1 >> level); ++px)
    {
      if (!this->IsOpaque(level, px, py, x0, y0, x1, y1))
      {
        return false;
      }
    }
  }
  return true;
}
