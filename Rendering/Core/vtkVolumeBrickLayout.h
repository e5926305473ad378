// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkVolumeBrickLayout
 * @brief   how a volume is split into bricks that the GPU can hold, and the order to draw them
 *
 * A volume of Dimensions points is cut along each axis into pieces of whole cells, as equal as
 * possible; the bricks are the products of the pieces. Every cell belongs to exactly one brick
 * (its owned cells, half-open [lo, hi) per axis), so that a renderer that integrates each
 * brick's own cells and composites the bricks in visibility order draws what one piece would.
 * A brick's texture holds its owned cells' points plus GhostPoints more on each side (clamped
 * to the volume): what a sample near the brick's faces reads beyond them (a segment's far end,
 * a gradient's neighbours).
 *
 * The pieces are as few as the limits allow: a brick's texture has at most MaximumBrickPoints
 * points along each axis and at most MaximumBrickBytes bytes at BytesPerPoint. Update()
 * computes the layout; it is an error when no split meets the limits (ghosts that leave no
 * room for a cell).
 *
 * GetBackToFront() orders the bricks for a viewer so that any brick a ray meets later is
 * drawn earlier: along a ray every brick index moves away from the viewer on each axis, so
 * the sum over the axes of how far a brick lies from the viewer's slab, in pieces, grows
 * strictly along the ray; bricks are drawn by decreasing sum.
 */
#ifndef vtkVolumeBrickLayout_h
#define vtkVolumeBrickLayout_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkObject.h"

#include <vector> // For std::vector

class vtkIdList;

class HOVRRENDERINGCORE_EXPORT vtkVolumeBrickLayout : public vtkObject
{
public:
  static vtkVolumeBrickLayout* New();
  vtkTypeMacro(vtkVolumeBrickLayout, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Points of the volume along each axis, at least 2. Initial value is 2 x 2 x 2.
   */
  vtkSetVector3Macro(Dimensions, int);
  vtkGetVector3Macro(Dimensions, int);
  ///@}

  ///@{
  /**
   * Points each brick's texture holds beyond its owned cells on each side. Initial value is 0.
   */
  vtkSetClampMacro(GhostPoints, int, 0, 4096);
  vtkGetMacro(GhostPoints, int);
  ///@}

  ///@{
  /**
   * The most points of a brick's texture along an axis, ghosts included (the GPU's
   * GL_MAX_3D_TEXTURE_SIZE, or less). Initial value is 2048.
   */
  vtkSetClampMacro(MaximumBrickPoints, int, 2, 1 << 20);
  vtkGetMacro(MaximumBrickPoints, int);
  ///@}

  ///@{
  /**
   * The most bytes of a brick's texture. Initial value is 1 GiB.
   */
  vtkSetClampMacro(MaximumBrickBytes, double, 1.0, 1e18);
  vtkGetMacro(MaximumBrickBytes, double);
  ///@}

  ///@{
  /**
   * Bytes of one point in a brick's texture. Initial value is 4.
   */
  vtkSetClampMacro(BytesPerPoint, int, 1, 1024);
  vtkGetMacro(BytesPerPoint, int);
  ///@}

  /**
   * Compute the layout. False, after an error, when no split meets the limits.
   */
  bool Update();

  /**
   * Bricks of the last Update() (0 after a failed one), and pieces along each axis.
   */
  int GetNumberOfBricks() const;
  void GetNumberOfPieces(int pieces[3]) const;

  /**
   * Brick b's owned cells, half-open: cells [lo, hi) along axis a are cells[2a], cells[2a+1].
   */
  void GetBrickCells(int b, int cells[6]) const;

  /**
   * Brick b's texture points, inclusive: its owned cells' points widened by GhostPoints and
   * clamped to the volume.
   */
  void GetBrickPoints(int b, int points[6]) const;

  /**
   * Brick b's texture size in points.
   */
  void GetBrickSize(int b, int size[3]) const;

  /**
   * The bricks in drawing order, back to front, for a viewer at `point` (0-based continuous
   * grid index) looking in any direction, or, when parallel is true, for parallel rays along
   * the grid-index direction `point`.
   */
  void GetBackToFront(const double point[3], bool parallel, vtkIdList* order) const;

protected:
  vtkVolumeBrickLayout();
  ~vtkVolumeBrickLayout() override;

  int Dimensions[3] = { 2, 2, 2 };
  int GhostPoints = 0;
  int MaximumBrickPoints = 2048;
  double MaximumBrickBytes = 1073741824.0;
  int BytesPerPoint = 4;

private:
  vtkVolumeBrickLayout(const vtkVolumeBrickLayout&) = delete;
  void operator=(const vtkVolumeBrickLayout&) = delete;

  // Where each axis is cut, in cells: pieces + 1 values from 0 to the cells. Brick
  // i + pieces[0] (j + pieces[1] k) is piece i along x, j along y and k along z.
  std::vector<int> Cuts[3];
};

#endif
