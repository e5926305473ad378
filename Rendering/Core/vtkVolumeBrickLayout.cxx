// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkVolumeBrickLayout.h"

#include "vtkIdList.h"
#include "vtkObjectFactory.h"

#include <algorithm>
#include <numeric>

vtkStandardNewMacro(vtkVolumeBrickLayout);

//------------------------------------------------------------------------------
vtkVolumeBrickLayout::vtkVolumeBrickLayout() = default;

//------------------------------------------------------------------------------
vtkVolumeBrickLayout::~vtkVolumeBrickLayout() = default;

//------------------------------------------------------------------------------
bool vtkVolumeBrickLayout::Update()
{
  for (auto& cuts : this->Cuts)
  {
    cuts.clear();
  }
  int cells[3], pieces[3] = { 1, 1, 1 };
  for (int a = 0; a < 3; ++a)
  {
    if (this->Dimensions[a] < 2)
    {
      vtkErrorMacro("The volume needs at least 2 points along each axis; it has "
        << this->Dimensions[0] << " x " << this->Dimensions[1] << " x " << this->Dimensions[2]
        << ".");
      return false;
    }
    cells[a] = this->Dimensions[a] - 1;
  }
  // Texture points of the largest piece along an axis: its cells' points and the ghosts.
  auto points = [&](int a)
  {
    const int largest = (cells[a] + pieces[a] - 1) / pieces[a];
    return std::min(largest + 1 + 2 * this->GhostPoints, this->Dimensions[a]);
  };
  for (int a = 0; a < 3; ++a)
  {
    while (points(a) > this->MaximumBrickPoints && pieces[a] < cells[a])
    {
      ++pieces[a];
    }
    if (points(a) > this->MaximumBrickPoints)
    {
      vtkErrorMacro("A brick of one cell with "
        << this->GhostPoints << " ghost points a side needs " << points(a)
        << " points along an axis, more than " << this->MaximumBrickPoints << ".");
      return false;
    }
  }
  for (;;)
  {
    const double bytes =
      static_cast<double>(points(0)) * points(1) * points(2) * this->BytesPerPoint;
    if (bytes <= this->MaximumBrickBytes)
    {
      break;
    }
    // Split further along the axis with the most texture points that can still be split.
    int axis = -1;
    for (int a = 0; a < 3; ++a)
    {
      if (pieces[a] < cells[a] && (axis < 0 || points(a) > points(axis)))
      {
        axis = a;
      }
    }
    if (axis < 0)
    {
      vtkErrorMacro("Bricks of one cell take " << bytes << " bytes with " << this->GhostPoints
                                               << " ghost points a side, more than "
                                               << this->MaximumBrickBytes << ".");
      return false;
    }
    ++pieces[axis];
  }
  for (int a = 0; a < 3; ++a)
  {
    this->Cuts[a].resize(static_cast<size_t>(pieces[a]) + 1);
    for (int p = 0; p <= pieces[a]; ++p)
    {
      this->Cuts[a][p] = static_cast<int>(static_cast<long long>(p) * cells[a] / pieces[a]);
    }
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkVolumeBrickLayout::GetNumberOfBricks() const
{
  int bricks = 1;
  for (const auto& cuts : this->Cuts)
  {
    bricks *= cuts.empty() ? 0 : static_cast<int>(cuts.size()) - 1;
  }
  return bricks;
}

//------------------------------------------------------------------------------
void vtkVolumeBrickLayout::GetNumberOfPieces(int pieces[3]) const
{
  for (int a = 0; a < 3; ++a)
  {
    pieces[a] = this->Cuts[a].empty() ? 0 : static_cast<int>(this->Cuts[a].size()) - 1;
  }
}

//------------------------------------------------------------------------------
void vtkVolumeBrickLayout::GetBrickCells(int b, int cells[6]) const
{
  int pieces[3];
  this->GetNumberOfPieces(pieces);
  int index[3] = { b % std::max(pieces[0], 1),
    (b / std::max(pieces[0], 1)) % std::max(pieces[1], 1),
    b / std::max(pieces[0] * pieces[1], 1) };
  for (int a = 0; a < 3; ++a)
  {
    const bool valid = b >= 0 && b < this->GetNumberOfBricks();
    cells[2 * a] = valid ? this->Cuts[a][index[a]] : 0;
    cells[2 * a + 1] = valid ? this->Cuts[a][index[a] + 1] : 0;
  }
}

//------------------------------------------------------------------------------
void vtkVolumeBrickLayout::GetBrickPoints(int b, int points[6]) const
{
  int cells[6];
  this->GetBrickCells(b, cells);
  for (int a = 0; a < 3; ++a)
  {
    points[2 * a] = std::max(cells[2 * a] - this->GhostPoints, 0);
    points[2 * a + 1] = std::min(cells[2 * a + 1] + this->GhostPoints, this->Dimensions[a] - 1);
  }
}

//------------------------------------------------------------------------------
void vtkVolumeBrickLayout::GetBrickSize(int b, int size[3]) const
{
  int points[6];
  this->GetBrickPoints(b, points);
  for (int a = 0; a < 3; ++a)
  {
    size[a] = points[2 * a + 1] - points[2 * a] + 1;
  }
}

//------------------------------------------------------------------------------
void vtkVolumeBrickLayout::GetBackToFront(const double point[3],
  bool parallel,
  vtkIdList* order) const
{
  order->Reset();
  const int bricks = this->GetNumberOfBricks();
  int pieces[3];
  this->GetNumberOfPieces(pieces);
  // Per axis, each piece's rank: how far it lies from the viewer, in pieces.
  std::vector<int> rank[3];
  for (int a = 0; a < 3; ++a)
  {
    rank[a].resize(static_cast<size_t>(pieces[a]));
    // The viewer's slab: the piece holding its coordinate (-1 or pieces when outside); for
    // parallel rays, the side they come from.
    int slab = 0;
    if (parallel)
    {
      slab = point[a] > 0.0 ? -1 : point[a] < 0.0 ? pieces[a] : 0;
    }
    else
    {
      slab =
        static_cast<int>(std::upper_bound(this->Cuts[a].begin(), this->Cuts[a].end(), point[a]) -
          this->Cuts[a].begin()) -
        1;
    }
    for (int p = 0; p < pieces[a]; ++p)
    {
      rank[a][p] = parallel && point[a] == 0.0 ? 0 : std::abs(p - slab);
    }
  }
  std::vector<int> key(static_cast<size_t>(bricks)), ids(static_cast<size_t>(bricks));
  for (int b = 0; b < bricks; ++b)
  {
    const int i = b % pieces[0], j = (b / pieces[0]) % pieces[1], k = b / (pieces[0] * pieces[1]);
    key[b] = rank[0][i] + rank[1][j] + rank[2][k];
  }
  std::iota(ids.begin(), ids.end(), 0);
  std::stable_sort(ids.begin(), ids.end(), [&](int x, int y) { return key[x] > key[y]; });
  for (int id : ids)
  {
    order->InsertNextId(id);
  }
}

//------------------------------------------------------------------------------
void vtkVolumeBrickLayout::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Dimensions: " << this->Dimensions[0] << " " << this->Dimensions[1] << " "
     << this->Dimensions[2] << "\n";
  os << indent << "GhostPoints: " << this->GhostPoints << "\n";
  os << indent << "MaximumBrickPoints: " << this->MaximumBrickPoints << "\n";
  os << indent << "MaximumBrickBytes: " << this->MaximumBrickBytes << "\n";
  os << indent << "BytesPerPoint: " << this->BytesPerPoint << "\n";
  os << indent << "NumberOfBricks: " << this->GetNumberOfBricks() << "\n";
}
