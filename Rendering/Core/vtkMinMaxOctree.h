// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkMinMaxOctree
 * @brief   min-max octree over the cells of a grid of point scalars
 *
 * The space-leaping structure of Mora, Jessel and Caubet's object-order ray caster (section
 * 4.1): a node stores the smallest and largest scalar of the points of its cells, so the
 * trilinear interpolant inside the node stays within that range, and whether a node can be
 * seen is decided at render time from the current opacity transfer function
 * (vtkVolumeTransferFunctionSampler::GetMaximumOpacity over the range): editing the transfer
 * function costs no rebuild. Built once per volume.
 *
 * Level 0 is the cells themselves and is not stored (a renderer loads a cell's 8 corners
 * anyway). Level l >= 1 has nodes of 2^l x 2^l x 2^l cells, ceil(cells / 2^l) per axis (the
 * last ones truncated), up to the root level GetNumberOfLevels(), which has one node; a grid
 * of one cell has no stored level. Ranges are floats rounded outwards from the data, so they
 * always contain it; NaN points are ignored, and a node with only NaN points gets the empty
 * range (+inf, -inf). Memory: 8 bytes per node, about 8/7 of a byte per cell.
 */
#ifndef vtkMinMaxOctree_h
#define vtkMinMaxOctree_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkObject.h"

#include <vector> // For std::vector

class vtkDataArray;
class vtkImageData;

class HOVRRENDERINGCORE_EXPORT vtkMinMaxOctree : public vtkObject
{
public:
  static vtkMinMaxOctree* New();
  vtkTypeMacro(vtkMinMaxOctree, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Build over single-component point scalars on a grid of dims points (x fastest).
   * Returns false and reports an error for a missing or multi-component array, a size that
   * does not match dims, or a grid with fewer than 2 points along an axis; the octree is then
   * empty. When its levels cannot be allocated, std::bad_alloc propagates, as from the
   * standard containers that hold them (vtkObjectOrderRayCaster catches it and calls
   * Initialize()).
   */
  bool Build(vtkDataArray* scalars, const int dims[3]);

  /**
   * Empty the octree and free its levels.
   */
  void Initialize();

  /**
   * Build over the point scalars of an image.
   */
  bool Build(vtkImageData* image);

  /**
   * The root level: the number of stored levels (0 for a grid of one cell or an empty octree).
   */
  int GetNumberOfLevels() const { return static_cast<int>(this->Levels.size()); }

  /**
   * Nodes per axis at a level (level 0: the cells). Zeros when the level does not exist.
   */
  void GetLevelSize(int level, int size[3]) const;

  /**
   * Range (min, max) of node (i, j, k) of a stored level (1 .. GetNumberOfLevels()). Indices
   * are not checked.
   */
  void GetNodeRange(int level, int i, int j, int k, float range[2]) const
  {
    const Level& l = this->Levels[level - 1];
    const float* r = l.Ranges.data() +
      2 * (i + static_cast<size_t>(l.Size[0]) * (j + static_cast<size_t>(l.Size[1]) * k));
    range[0] = r[0];
    range[1] = r[1];
  }

  /**
   * Bytes held by the stored levels.
   */
  vtkIdType GetMemorySize() const;

  /**
   * Number of builds so far (a renderer reuses the octree while the data do not change).
   */
  vtkGetMacro(BuildCount, int);

protected:
  vtkMinMaxOctree();
  ~vtkMinMaxOctree() override;

  struct Level
  {
    int Size[3];
    std::vector<float> Ranges; // (min, max) per node, x fastest
  };
  std::vector<Level> Levels; // Levels[l - 1] is level l
  int Cells[3] = { 0, 0, 0 };
  int BuildCount = 0;

private:
  vtkMinMaxOctree(const vtkMinMaxOctree&) = delete;
  void operator=(const vtkMinMaxOctree&) = delete;
};

#endif
