// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkObjectOrderRayCasterRays
 * @brief   the pixel rays of vtkObjectOrderRayCaster's parallel view, in grid index
 *
 * Pixel (i, j)'s ray is O + i EX + j EY + t D in grid index (0-based from the extent's first
 * point), t the world distance from the camera plane; (u, v) = Inverse rows 0-1 applied to
 * (p - O) project a grid point to pixel coordinates. Every cell of a parallel view projects to
 * the same shape, which the octree's screen tests and the leaves' rectangles rely on. Chord
 * and Rectangle are compiled out of line, without the AVX2 copy's fused multiply-adds, so that
 * both copies of the tile walk find the same chords and rectangles.
 *
 * Part of vtkObjectOrderRayCaster's frame: a value class for its inner loops (not a
 * vtkObject, not wrapped, not installed).
 */
#ifndef vtkObjectOrderRayCasterRays_h
#define vtkObjectOrderRayCasterRays_h

class vtkCameraRayModel;
class vtkMatrix4x4;

class vtkObjectOrderRayCasterRays
{
public:
  /**
   * The rays of the ray model's width x height image (size, at least 1 x 1) through a grid of
   * `cells` cells, worldToIndex taking world points to grid index, with samples `step` apart:
   * the rays start a whole number of steps after the camera plane, and VolumePixels is found.
   */
  void Update(vtkCameraRayModel* model,
    vtkMatrix4x4* worldToIndex,
    const int size[2],
    const int cells[3],
    double step);

  /**
   * For a piece of a volume with ghost points: the whole volume's box [wholeLo, wholeHi]
   * (grid index, which Chord clips to instead of the points' box) and the points the piece owns,
   * [ownedLo, ownedHi] (grid index), with extent, the structured index of the grid's first
   * point, and toStructured, world to structured index (the same on every piece).
   */
  void SetPiece(const double wholeLo[3],
    const double wholeHi[3],
    const int ownedLo[3],
    const int ownedHi[3],
    const int extent[3],
    vtkMatrix4x4* toStructured,
    vtkCameraRayModel* model);

  /**
   * Where pixel (i, j)'s ray enters and leaves the box of the points (t), or the whole
   * volume's box of a piece: te > tx, or tx < 0, when it misses.
   */
  void Chord(int i, int j, double& te, double& tx) const;

  /**
   * The samples of pixel (i, j)'s ray with phase `phase` that its piece draws, n in
   * [range[0], range[1]) (the sample at phase + n step): those in the owned points, a sample
   * on a face that two pieces share going to the piece behind it along the axis. Found from
   * the structured index in the same operations on every piece, so that the pieces' ranges
   * never overlap nor leave a gap. All of them, (-inf, inf), without a piece.
   */
  void OwnedSamples(int i, int j, double phase, double range[2]) const;

  /**
   * Pixel rectangle of the box [lo, hi] (grid index) clipped to [x0, x1] x [y0, y1]; false
   * when empty. Pixel i's ray passes through u = i, so the pixels whose rays can meet the box
   * lie within its projection's extent.
   */
  bool Rectangle(const double lo[3], const double hi[3], const int clip[4], int rect[4]) const;

  double O[3], EX[3], EY[3], D[3], InvD[3];
  bool Still[3];
  double Inverse[3][3];
  double WorldDirection[3]; // D in world coordinates
  int Width = 0, Height = 0;
  int Cells[3] = { 0, 0, 0 };
  double Step = 1.0;
  // Whole steps the rays' origin O lies past the camera plane.
  double SkippedSteps = 0.0;
  // The box Chord clips to: the points' own, or a piece's whole volume's.
  double ChordLo[3] = { 0.0, 0.0, 0.0 }, ChordHi[3] = { 0.0, 0.0, 0.0 };
  // A piece: its rays on the camera plane in structured index, its owned box in structured
  // index, and which of that box's faces it shares with another piece (low, high per axis).
  bool Piece = false;
  double StructuredO[3], StructuredEX[3], StructuredEY[3];
  double OwnedLo[3], OwnedHi[3];
  bool Shared[6];
  // The pixels whose rays can meet the grid's box (empty: x0 > x1); the tiles outside it
  // keep the output's zeros.
  int VolumePixels[4] = { 0, -1, 0, -1 };
};

#endif
