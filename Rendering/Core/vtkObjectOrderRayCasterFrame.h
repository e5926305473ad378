// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkObjectOrderRayCasterFrame
 * @brief   everything the tiles of vtkObjectOrderRayCaster share, read-only during a frame
 *
 * The bricked volume, the classification tables, the shading, the pixel rays and the frame's
 * settings. The caster updates it before the tiles are walked (vtkObjectOrderRayCasterTiles);
 * the volume and the tables persist across frames, rebuilt only when what they were built for
 * changes.
 *
 * Part of vtkObjectOrderRayCaster: a value class for its inner loops (not a vtkObject, not
 * wrapped, not installed).
 */
#ifndef vtkObjectOrderRayCasterFrame_h
#define vtkObjectOrderRayCasterFrame_h

#include "vtkObjectOrderRayCasterBricks.h"         // For vtkObjectOrderRayCasterBricks
#include "vtkObjectOrderRayCasterClassification.h" // For vtkObjectOrderRayCasterClassification
#include "vtkObjectOrderRayCasterRays.h"           // For vtkObjectOrderRayCasterRays
#include "vtkObjectOrderRayCasterShading.h"        // For vtkObjectOrderRayCasterShading

class vtkObjectOrderRayCasterFrame
{
public:
  /**
   * Free the copies of the volume (the bricks and the quantized normals), so that the memory
   * goes back and the next update starts again from the scalars.
   */
  void ReleaseVolume()
  {
    this->Volume.Release();
    this->Shading.ReleaseNormals();
  }

  vtkObjectOrderRayCasterBricks Volume;
  vtkObjectOrderRayCasterClassification Classification;
  vtkObjectOrderRayCasterShading Shading;
  vtkObjectOrderRayCasterRays Rays;
  double Step = 1.0;
  bool Interleaved = true;
  bool Removal = true;
  float Threshold = 0.996f;
  // The octree level whose nodes are rendered as a whole (leaves of 2^LeafLevel cells per
  // edge).
  int LeafLevel = 0;
  // Whether the frame is complete: the tiles can be walked (again, for counting).
  bool Ready = false;
};

#endif
