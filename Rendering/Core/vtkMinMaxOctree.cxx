// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkMinMaxOctree.h"

#include "vtkArrayDispatch.h"
#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkImageData.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <limits>

vtkStandardNewMacro(vtkMinMaxOctree);

namespace
{
// The float range containing [lo, hi]: rounded outwards.
void OutwardRange(double lo, double hi, float range[2])
{
  const float inf = std::numeric_limits<float>::infinity();
  if (!(lo <= hi))
  {
    range[0] = inf;
    range[1] = -inf;
    return;
  }
  float l = static_cast<float>(lo), h = static_cast<float>(hi);
  if (static_cast<double>(l) > lo)
  {
    l = std::nextafter(l, -inf);
  }
  if (static_cast<double>(h) < hi)
  {
    h = std::nextafter(h, inf);
  }
  range[0] = l;
  range[1] = h;
}

// Level 1 straight from the points: node (i, j, k) covers points 2i .. min(2i + 2, n - 1).
struct FirstLevelWorker
{
  template <typename ArrayT>
  void operator()(ArrayT* array, const int dims[3], const int size[3], float* ranges) const
  {
    const auto values = vtk::DataArrayValueRange<1>(array);
    const vtkIdType sy = dims[0], sz = static_cast<vtkIdType>(dims[0]) * dims[1];
    vtkSMPTools::For(0,
      size[2],
      [&](vtkIdType k0, vtkIdType k1)
      {
        for (vtkIdType k = k0; k < k1; ++k)
        {
          for (int j = 0; j < size[1]; ++j)
          {
            for (int i = 0; i < size[0]; ++i)
            {
              double lo = std::numeric_limits<double>::infinity(), hi = -lo;
              const int pk1 = std::min(2 * static_cast<int>(k) + 2, dims[2] - 1);
              const int pj1 = std::min(2 * j + 2, dims[1] - 1);
              const int pi1 = std::min(2 * i + 2, dims[0] - 1);
              for (int pk = 2 * static_cast<int>(k); pk <= pk1; ++pk)
              {
                for (int pj = 2 * j; pj <= pj1; ++pj)
                {
                  for (int pi = 2 * i; pi <= pi1; ++pi)
                  {
                    const double v = static_cast<double>(values[pi + pj * sy + pk * sz]);
                    // NaN compares false both ways and is left out.
                    lo = v < lo ? v : lo;
                    hi = v > hi ? v : hi;
                  }
                }
              }
              OutwardRange(lo,
                hi,
                ranges +
                  2 * (i + static_cast<size_t>(size[0]) * (j + static_cast<size_t>(size[1]) * k)));
            }
          }
        }
      });
  }
};
}

//------------------------------------------------------------------------------
vtkMinMaxOctree::vtkMinMaxOctree() = default;

//------------------------------------------------------------------------------
vtkMinMaxOctree::~vtkMinMaxOctree() = default;

//------------------------------------------------------------------------------
bool vtkMinMaxOctree::Build(vtkImageData* image)
{
  if (!image)
  {
    vtkErrorMacro("No image to build the octree over.");
    this->Levels.clear();
    return false;
  }
  int dims[3];
  image->GetDimensions(dims);
  return this->Build(image->GetPointData()->GetScalars(), dims);
}

//------------------------------------------------------------------------------
void vtkMinMaxOctree::Initialize()
{
  std::vector<Level>().swap(this->Levels);
  std::fill(this->Cells, this->Cells + 3, 0);
}

//------------------------------------------------------------------------------
bool vtkMinMaxOctree::Build(vtkDataArray* scalars, const int dims[3])
{
  this->Levels.clear();
  std::fill(this->Cells, this->Cells + 3, 0);
  if (!scalars)
  {
    vtkErrorMacro("No scalars to build the octree over.");
    return false;
  }
  if (scalars->GetNumberOfComponents() != 1)
  {
    vtkErrorMacro("The octree is built over single-component scalars; '"
      << (scalars->GetName() ? scalars->GetName() : "") << "' has "
      << scalars->GetNumberOfComponents() << " components.");
    return false;
  }
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2)
  {
    vtkErrorMacro("The grid needs at least 2 points along each axis to have a cell; it has "
      << dims[0] << " x " << dims[1] << " x " << dims[2] << ".");
    return false;
  }
  if (scalars->GetNumberOfTuples() != static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2])
  {
    vtkErrorMacro("The scalars have " << scalars->GetNumberOfTuples() << " tuples for a grid of "
                                      << dims[0] << " x " << dims[1] << " x " << dims[2]
                                      << " points.");
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    this->Cells[a] = dims[a] - 1;
  }
  // Level l has ceil(cells / 2^l) nodes per axis, down to one node.
  int size[3] = { this->Cells[0], this->Cells[1], this->Cells[2] };
  while (size[0] > 1 || size[1] > 1 || size[2] > 1)
  {
    Level level;
    for (int a = 0; a < 3; ++a)
    {
      level.Size[a] = size[a] = (size[a] + 1) / 2;
    }
    level.Ranges.resize(2 * static_cast<size_t>(size[0]) * size[1] * size[2]);
    this->Levels.push_back(std::move(level));
  }
  if (this->Levels.empty())
  {
    ++this->BuildCount;
    this->Modified();
    return true;
  }
  FirstLevelWorker first;
  Level& l1 = this->Levels[0];
  if (!vtkArrayDispatch::Dispatch::Execute(scalars, first, dims, l1.Size, l1.Ranges.data()))
  {
    first(scalars, dims, l1.Size, l1.Ranges.data());
  }
  // Each higher node combines its (up to) 8 children.
  for (size_t li = 1; li < this->Levels.size(); ++li)
  {
    const Level& child = this->Levels[li - 1];
    Level& parent = this->Levels[li];
    vtkSMPTools::For(0,
      parent.Size[2],
      [&](vtkIdType k0, vtkIdType k1)
      {
        for (vtkIdType k = k0; k < k1; ++k)
        {
          for (int j = 0; j < parent.Size[1]; ++j)
          {
            for (int i = 0; i < parent.Size[0]; ++i)
            {
              float lo = std::numeric_limits<float>::infinity(), hi = -lo;
              for (int ck = 2 * static_cast<int>(k);
                   ck < std::min(2 * static_cast<int>(k) + 2, child.Size[2]);
                   ++ck)
              {
                for (int cj = 2 * j; cj < std::min(2 * j + 2, child.Size[1]); ++cj)
                {
                  for (int ci = 2 * i; ci < std::min(2 * i + 2, child.Size[0]); ++ci)
                  {
                    const float* r = child.Ranges.data() +
                      2 *
                        (ci +
                          static_cast<size_t>(child.Size[0]) *
                            (cj + static_cast<size_t>(child.Size[1]) * ck));
                    lo = std::min(lo, r[0]);
                    hi = std::max(hi, r[1]);
                  }
                }
              }
              float* r = parent.Ranges.data() +
                2 *
                  (i +
                    static_cast<size_t>(parent.Size[0]) *
                      (j + static_cast<size_t>(parent.Size[1]) * k));
              r[0] = lo;
              r[1] = hi;
            }
          }
        }
      });
  }
  ++this->BuildCount;
  this->Modified();
  return true;
}

//------------------------------------------------------------------------------
void vtkMinMaxOctree::GetLevelSize(int level, int size[3]) const
{
  if (level == 0)
  {
    std::copy(this->Cells, this->Cells + 3, size);
  }
  else if (level >= 1 && level <= this->GetNumberOfLevels())
  {
    std::copy(this->Levels[level - 1].Size, this->Levels[level - 1].Size + 3, size);
  }
  else
  {
    std::fill(size, size + 3, 0);
  }
}

//------------------------------------------------------------------------------
vtkIdType vtkMinMaxOctree::GetMemorySize() const
{
  vtkIdType bytes = 0;
  for (const Level& level : this->Levels)
  {
    bytes += static_cast<vtkIdType>(level.Ranges.size() * sizeof(float));
  }
  return bytes;
}

//------------------------------------------------------------------------------
void vtkMinMaxOctree::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Cells: " << this->Cells[0] << " " << this->Cells[1] << " " << this->Cells[2]
     << "\n";
  os << indent << "NumberOfLevels: " << this->GetNumberOfLevels() << "\n";
  os << indent << "MemorySize: " << this->GetMemorySize() << "\n";
  os << indent << "BuildCount: " << this->BuildCount << "\n";
}
