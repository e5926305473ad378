// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkObjectOrderRayCasterTiles
 * @brief   the tiles of vtkObjectOrderRayCaster's image, walked in parallel
 *
 * The image is cut into tiles rendered in parallel with vtkSMPTools, each by its own tile
 * walker with its own occlusion map, so the image does not depend on the number of threads.
 * The walk and its sample loop are compiled twice: for any x86-64 processor (SSE2) and, with
 * GCC or Clang on x86-64, for those with AVX2 and FMA, where fused multiply-adds shorten the
 * chains of dependent operations of a sample and the unshaded rays of a leaf are sampled
 * eight at a time. Every class of the walk has internal linkage in this class's file, so
 * neither copy stands in for the other at link time.
 *
 * Part of vtkObjectOrderRayCaster (not a vtkObject, not wrapped, not installed).
 */
#ifndef vtkObjectOrderRayCasterTiles_h
#define vtkObjectOrderRayCasterTiles_h

#include "vtkType.h" // For vtkIdType, vtkTypeBool

class vtkMinMaxOctree;
class vtkObjectOrderRayCasterFrame;

class vtkObjectOrderRayCasterTiles
{
public:
  /**
   * Whether this build has the AVX2 copy and the processor runs it.
   */
  static bool HasAVX2();

  /**
   * Walk tiles [begin, end) of the frame's image (tiles of tileSize pixels, row by row) in
   * parallel, with the AVX2 copy or the SSE2 one, into image (RGBA, Width x Height): each
   * tile writes every one of its pixels. A tile outside the volume's pixels, or any once
   * abort is set, is cleared instead. Adds the octree nodes visited and the samples taken to
   * nodes and samples.
   */
  static void Walk(const vtkObjectOrderRayCasterFrame& frame,
    const vtkMinMaxOctree* octree,
    bool avx2,
    int tileSize,
    vtkIdType begin,
    vtkIdType end,
    const vtkTypeBool& abort,
    float* image,
    vtkIdType& nodes,
    vtkIdType& samples);

  /**
   * The non-transparent cells of the frame whose screen rectangle meets the image: the octree
   * walked down to the cells, without sampling or hidden volume removal.
   */
  static vtkIdType CountNonTransparentCells(const vtkObjectOrderRayCasterFrame& frame,
    const vtkMinMaxOctree* octree);
};

#endif
