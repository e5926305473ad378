// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkObjectOrderRayCasterBricks
 * @brief   the volume of vtkObjectOrderRayCaster in float bricks, with their visible cells
 *
 * The volume is kept in bricks of 8^3 cells that hold their far faces too (9^3 points), so
 * that any leaf of the octree (at most 8^3 cells, aligned) lies in one brick with its points
 * at fixed strides (section 4.3.4's aim: a cell's corners and its neighbours share cache
 * lines), at 1.42 times the memory of a plain float copy. Each brick keeps a bit per cell for
 * the cells that are visible under the current classification (found when a ray first needs
 * them, once per transfer function rather than once per frame) and a bit per cell for the
 * cells a ray took a sample in during the frame (counted once per cell at its end).
 *
 * Part of vtkObjectOrderRayCaster's frame: a value class for its inner loops (not a
 * vtkObject, not wrapped, not installed).
 */
#ifndef vtkObjectOrderRayCasterBricks_h
#define vtkObjectOrderRayCasterBricks_h

#include "vtkType.h" // For vtkMTimeType, vtkIdType

#include <algorithm> // For std::min
#include <atomic>    // For std::atomic
#include <cmath>     // For std::isfinite
#include <cstddef>   // For size_t
#include <cstdint>   // For uint64_t
#include <limits>    // For std::numeric_limits
#include <memory>    // For std::unique_ptr
#include <vector>    // For std::vector

class vtkDataArray;
class vtkObjectOrderRayCasterClassification;

class vtkObjectOrderRayCasterBricks
{
public:
  static constexpr int BrickCells = 8;
  static constexpr int BrickPoints = BrickCells + 1;
  static constexpr int BrickValues = BrickPoints * BrickPoints * BrickPoints;
  static constexpr int BrickWords = BrickCells * BrickCells * BrickCells / 64; // a bit per cell

  /**
   * Bricks along an axis of `points` points (at least one, for a flat axis).
   */
  static int BrickCountAlong(int points);

  /**
   * Whether the bricks hold these scalars, as they are now, on a grid of these dimensions.
   */
  bool IsBuiltFor(vtkDataArray* scalars, const int dims[3]) const;

  /**
   * Copy the scalars (dims points) into bricks; every brick's visible cells are to be found
   * again. Throws std::bad_alloc when the memory runs out: Release() then frees what was
   * allocated.
   */
  void Build(vtkDataArray* scalars, const int dims[3]);

  /**
   * Free the copy (not just empty it), so that the memory goes back and the next Build starts
   * again from the scalars.
   */
  void Release();

  /**
   * The visible cells of every brick are to be found again (the classification changed).
   */
  void NewClassification();

  /**
   * The visible cells of brick b (at brick coordinates bc), a bit per cell x + 8 y + 64 z,
   * found the first time a ray needs them for this classification: a cell is visible when
   * its 8 corners are finite and the opacity may be non-zero in their range. Tiles racing for
   * the same brick find the same bits.
   */
  void BrickVisibility(size_t b,
    const int bc[3],
    const vtkObjectOrderRayCasterClassification& classification,
    uint64_t bits[BrickWords]) const;

  /**
   * The cells that rays took a sample in since the last call, each once; the bits are cleared
   * for the next frame.
   */
  vtkIdType CountSampledCells();

  /**
   * Bytes of the bricks and of their cell bits.
   */
  size_t GetMemorySize() const;

  /**
   * A point's address in Bricks (in the brick where it is not a far face, but for the
   * volume's far faces).
   */
  size_t Address(int x, int y, int z) const
  {
    return this->AxisAddress[0][x] + this->AxisAddress[1][y] + this->AxisAddress[2][z];
  }

  /**
   * The 8 corners of cell (i, j, k), indexed x + 2 y + 4 z, and their range; false when one
   * is not finite (NaN or infinite: the cell is transparent).
   */
  bool Corners(int i, int j, int k, float c[8], float& lo, float& hi) const
  {
    bool finite = true;
    lo = std::numeric_limits<float>::infinity();
    hi = -lo;
    for (int n = 0; n < 8; ++n)
    {
      c[n] = this->Bricks[this->Address(i + (n & 1), j + ((n >> 1) & 1), k + (n >> 2))];
      finite = finite && std::isfinite(c[n]);
      lo = std::min(lo, c[n]);
      hi = std::max(hi, c[n]);
    }
    return finite;
  }

  /**
   * Central-difference gradient at point (x, y, z) in grid index units (one-sided at the
   * border, 0 where a neighbour is not finite).
   */
  void Gradient(int x, int y, int z, float g[3]) const
  {
    const int p[3] = { x, y, z };
    for (int a = 0; a < 3; ++a)
    {
      int lo[3] = { x, y, z }, hi[3] = { x, y, z };
      lo[a] = std::max(p[a] - 1, 0);
      hi[a] = std::min(p[a] + 1, this->Dims[a] - 1);
      const float d = this->Bricks[this->Address(hi[0], hi[1], hi[2])] -
        this->Bricks[this->Address(lo[0], lo[1], lo[2])];
      g[a] = hi[a] > lo[a] && std::isfinite(d) ? d / static_cast<float>(hi[a] - lo[a]) : 0.0f;
    }
  }

  // The scalars the bricks were built from: not referenced, only compared.
  vtkDataArray* Scalars = nullptr;
  vtkMTimeType ScalarsTime = 0;
  int Dims[3] = { 0, 0, 0 };
  int Cells[3] = { 0, 0, 0 };
  int BrickCount[3] = { 0, 0, 0 };
  size_t BrickTotal = 0;
  // BrickValues per brick, bricks and their points x fastest.
  std::vector<float> Bricks;
  // Address(x, y, z) = AxisAddress[0][x] + AxisAddress[1][y] + AxisAddress[2][z].
  std::vector<size_t> AxisAddress[3];
  // Per brick, its visible cells for the classification of version VisibleVersion, and the
  // version they were found for.
  std::unique_ptr<std::atomic<uint64_t>[]> VisibleBits;
  std::unique_ptr<std::atomic<uint32_t>[]> VisibleVersions;
  uint32_t VisibleVersion = 0;
  // Per brick, its cells a ray took a sample in this frame (same bits), so that each cell
  // counts once whatever the tiles and rays.
  std::unique_ptr<std::atomic<uint64_t>[]> SampledBits;
};

#endif
