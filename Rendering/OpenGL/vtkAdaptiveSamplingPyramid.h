// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkAdaptiveSamplingPyramid
 * @brief   the GPU state and passes of vtkAdaptiveSamplingVolumeMapper's slice pyramid
 *
 * A value class of vtkAdaptiveSamplingVolumeMapper alone (neither wrapped nor installed): the
 * levels of the pyramid over the padded viewport (Sec. 3.2 of "Adaptive Sampling in Three
 * Dimensions for Volume Rendering on GPUs"), each with two sets of float32 render targets
 * written alternately (level l + 1 and the previous pass of level l are read while level l is
 * written: no feedback loop), and the pass loop: per slice, one full-screen pass of
 * hovrAdaptivePyramidLevel.glsl per level from l_slice down to 0 (Fig. 7). The mapper owns the
 * camera, the slice grid and the volume, oracle and table textures; this class draws with them
 * and hands back the level-0 image and the operation counters.
 */
#ifndef vtkAdaptiveSamplingPyramid_h
#define vtkAdaptiveSamplingPyramid_h

#include "vtkSmartPointer.h" // For ivars
#include "vtkType.h"         // For vtkIdType

#include <memory> // For std::unique_ptr
#include <string> // For std::string
#include <vector> // For std::vector

class vtkOpenGLFramebufferObject;
class vtkOpenGLQuadHelper;
class vtkOpenGLRenderWindow;
class vtkOpenGLVolumeBricks;
class vtkTextureObject;
class vtkWindow;

class vtkAdaptiveSamplingPyramid
{
public:
  // What one frame draws: the slice grid in the volume's 0-based continuous grid index, the
  // settings and the textures (see hovrAdaptivePyramidLevel.glsl for each uniform).
  struct Frame
  {
    int MaximumLevel = 3;
    vtkIdType FirstSlice = 0;  // the first slice drawn, a multiple of 2^MaximumLevel
    vtkIdType LastSlice = 0;   // i_max
    int Width = 1, Height = 1; // the viewport, in level-0 pixels
    double RayOrigin[3] = { 0, 0, 0 }, RayAxisX[3] = { 0, 0, 0 }, RayAxisY[3] = { 0, 0, 0 };
    double SliceStep[3] = { 0, 0, 0 }, BoxMax[3] = { 1, 1, 1 }, AxisLength[3] = { 1, 1, 1 };
    double SliceSpacing = 1.0;
    // The whole volume's box in the same index (the input's box [0, BoxMax] unless it is a
    // piece of it).
    double WholeMin[3] = { 0, 0, 0 }, WholeMax[3] = { 1, 1, 1 };
    // A piece with ghost points: the rays in structured index, the owned points' box there,
    // and which of its faces (low, high per axis) it shares with other pieces.
    bool Piece = false;
    double StructuredOrigin[3] = { 0, 0, 0 }, StructuredAxisX[3] = { 0, 0, 0 };
    double StructuredAxisY[3] = { 0, 0, 0 }, StructuredStep[3] = { 0, 0, 0 };
    double OwnedLo[3] = { 0, 0, 0 }, OwnedHi[3] = { 0, 0, 0 };
    int SharedLo[3] = { 0, 0, 0 }, SharedHi[3] = { 0, 0, 0 };
    int TableSize = 256;
    bool MinimumOracle = false;
    bool EarlyTermination = true;
    // Counting covers every pixel; otherwise each level's pass covers only the pixels that
    // can matter, from Rectangle (level-0 pixels, first x, first y, last x, last y).
    bool Count = false;
    int Rectangle[4] = { 0, 0, 0, 0 };
    // The volume's and the oracle's bricks in atlas pages (the same pages and tiles, whose
    // uniforms Volume sets), the volume's raw values mapped to table indices by
    // raw * RawToIndex[0] + RawToIndex[1].
    vtkOpenGLVolumeBricks* Volume = nullptr;
    vtkOpenGLVolumeBricks* Oracle = nullptr;
    vtkTextureObject* Tables = nullptr;
    double RawToIndex[2] = { 1.0, 0.0 };
  };

  vtkAdaptiveSamplingPyramid();
  ~vtkAdaptiveSamplingPyramid();

  /**
   * Size levels + 1 levels over a width x height level-0 image (both divisible by 2^levels)
   * and compile the pass with the bricks' atlas defines. Keeps what exists when nothing
   * changed. Returns false when the pass does not compile (it needs GL_ARB_gpu_shader_fp64).
   */
  bool Prepare(vtkOpenGLRenderWindow* context,
    int levels,
    int width,
    int height,
    const std::string& atlasDefines);

  /**
   * Draw every slice of frame into the levels (the caller saves and restores the framebuffer
   * bindings). Returns the number of level passes drawn.
   */
  vtkIdType Draw(const Frame& frame);

  /**
   * Sums of the per-pixel counters of the last Draw() with Count on: samples, syntheses,
   * accumulates and boundary fetches (entry and exit scalars of level-0 pieces).
   */
  void ReadCounts(vtkIdType totals[4]);

  /**
   * The level-0 premultiplied image (C, alpha) of the last Draw(), padded size.
   */
  vtkTextureObject* GetImage();

  void ReleaseGraphicsResources(vtkWindow* window);

  /**
   * l_slice of Table 1 (line 76), as vtkAdaptiveSamplingRayCaster::SliceLevel.
   */
  static int SliceLevel(vtkIdType slice, int maximumLevel);

private:
  vtkAdaptiveSamplingPyramid(const vtkAdaptiveSamplingPyramid&) = delete;
  void operator=(const vtkAdaptiveSamplingPyramid&) = delete;

  // One level: two sets of render targets, written alternately; Current is the set the last
  // pass wrote (the one the next pass reads).
  struct Level
  {
    int Width = 0, Height = 0;
    vtkSmartPointer<vtkTextureObject> State[2], Counts[2], Previous[2], Colour[2];
    vtkSmartPointer<vtkOpenGLFramebufferObject> Targets[2];
    int Current = 0;
  };

  void Clear();

  std::vector<Level> Levels;
  std::unique_ptr<vtkOpenGLQuadHelper> Pass;
  std::string PassDefines;                  // the atlas defines the pass was compiled with
  vtkOpenGLRenderWindow* Context = nullptr; // not referenced: the window owns its resources
};

#endif
