// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// The leaves of vtkObjectOrderRayCaster's tile walk: where a leaf's points lie in its brick,
// which cell a position along a ray falls in, and the state a pixel's ray keeps between
// leaves. Included by vtkObjectOrderRayCasterTiles.cxx once per copy of the walk (SSE2, and
// AVX2 with FMA), inside its anonymous namespace; hence no include guard, and everything here
// has internal linkage.

// Trilinear interpolation of 8 corner values (x + 2 y + 4 z) at local coordinates u.
HOVR_ALWAYS_INLINE float Trilinear(const float v[8], const float u[3])
{
  const float x0 = v[0] + u[0] * (v[1] - v[0]);
  const float x1 = v[2] + u[0] * (v[3] - v[2]);
  const float x2 = v[4] + u[0] * (v[5] - v[4]);
  const float x3 = v[6] + u[0] * (v[7] - v[6]);
  const float y0 = x0 + u[1] * (x1 - x0);
  const float y1 = x2 + u[1] * (x3 - x2);
  return y0 + u[2] * (y1 - y0);
}

// Which cell of a leaf a point falls in: per axis c = Base + sign floor(Offset + sign x)
// clamped to [0, Last], where x is leaf-local and sign is -1 where the rays go down the axis,
// so that a point on a plane belongs to the cell the ray enters there (the cell after it
// along the ray), as a walk cell by cell would have it.
struct LeafCells
{
  float Direction[3];
  float Sign[3];
  float Offset[3];
  int Base[3];
  int Last[3];

  LeafCells(const float direction[3], const int size[3])
  {
    for (int a = 0; a < 3; ++a)
    {
      const bool down = direction[a] < 0.0f;
      this->Direction[a] = direction[a];
      this->Sign[a] = down ? -1.0f : 1.0f;
      this->Offset[a] = down ? static_cast<float>(size[a]) : 0.0f;
      this->Base[a] = down ? size[a] - 1 : 0;
      this->Last[a] = size[a] - 1;
    }
  }
};

// The cells of a leaf's ray segments: the cell and cell-local coordinates of a segment's
// point at entry + dt direction. Built once per leaf (its constants), then started at each
// segment's entry, so that a segment pays only for what changes along it. With SSE2 the three
// axes take one vector operation each; both paths give the same cells and coordinates.
class SegmentCells
{
public:
  explicit SegmentCells(const LeafCells& cells)
#ifdef HOVR_SSE2
    : Direction(_mm_setr_ps(cells.Direction[0], cells.Direction[1], cells.Direction[2], 0.0f))
    , Offset(_mm_setr_ps(cells.Offset[0], cells.Offset[1], cells.Offset[2], 0.0f))
    , Sign(_mm_setr_ps(cells.Sign[0], cells.Sign[1], cells.Sign[2], 1.0f))
    // Clamping the float below Last + 1 truncates to at most Last.
    , Top(_mm_setr_ps(cells.Last[0] + 0.5f, cells.Last[1] + 0.5f, cells.Last[2] + 0.5f, 0.0f))
    // -k is (k xor -1) - (-1): the sign applied without a multiply.
    , Down(_mm_setr_epi32(-(cells.Sign[0] < 0.0f),
        -(cells.Sign[1] < 0.0f),
        -(cells.Sign[2] < 0.0f),
        0))
    , Base(_mm_setr_epi32(cells.Base[0], cells.Base[1], cells.Base[2], 0))
#else
    : Cells(cells)
#endif
  {
  }

  // The segment's entry point, leaf-local.
  void Start(const float entry[3])
  {
#ifdef HOVR_SSE2
    this->Entry = _mm_setr_ps(entry[0], entry[1], entry[2], 0.0f);
#else
    std::copy(entry, entry + 3, this->Entry);
#endif
  }

  // The cell c (leaf-local) and the local coordinates u = x - c of the point at dt; four
  // entries each so that the vector path stores whole registers.
  void Locate(float dt, int c[4], float u[4]) const
  {
#ifdef HOVR_SSE2
    const __m128 x = _mm_add_ps(this->Entry, _mm_mul_ps(_mm_set1_ps(dt), this->Direction));
    // max before min: a NaN (never expected) becomes 0 rather than an out-of-leaf cell.
    const __m128 v = _mm_min_ps(
      _mm_max_ps(_mm_add_ps(this->Offset, _mm_mul_ps(this->Sign, x)), _mm_setzero_ps()), this->Top);
    // The truncation is a floor: v >= 0.
    const __m128i k = _mm_cvttps_epi32(v);
    const __m128i cell =
      _mm_add_epi32(_mm_sub_epi32(_mm_xor_si128(k, this->Down), this->Down), this->Base);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(c), cell);
    _mm_storeu_ps(u, _mm_sub_ps(x, _mm_cvtepi32_ps(cell)));
#else
    const LeafCells& cells = this->Cells;
    for (int a = 0; a < 3; ++a)
    {
      const float x = this->Entry[a] + dt * cells.Direction[a];
      // (The truncation is a floor: the argument is negative only by rounding.)
      const int k = static_cast<int>(cells.Offset[a] + cells.Sign[a] * x);
      c[a] =
        cells.Base[a] + static_cast<int>(cells.Sign[a]) * std::min(std::max(k, 0), cells.Last[a]);
      u[a] = x - static_cast<float>(c[a]);
    }
#endif
  }

private:
#ifdef HOVR_SSE2
  __m128 Entry = _mm_setzero_ps();
  const __m128 Direction, Offset, Sign, Top;
  const __m128i Down, Base;
#else
  const LeafCells Cells; // a copy: built from a temporary
  float Entry[3];
#endif
};

// A leaf of the octree inside its brick: its points (strides 1, BrickPoints, BrickPoints^2
// from its first one), the brick's visible cells (bits x + 8 y + 64 z) and the brick's
// cells the leaf's rays took samples in.
struct LeafView
{
  size_t Brick;
  int BrickCoordinates[3];
  const float* Points; // the leaf's first point
  int FirstCell;       // the brick's bit of the leaf's first cell
  int Local[3];        // the leaf's first cell in its brick
  uint64_t Visible[BrickWords];
  uint64_t Sampled[BrickWords] = {};

  LeafView(const Frame& I, const int lo[3])
  {
    int* local = this->Local;
    for (int a = 0; a < 3; ++a)
    {
      this->BrickCoordinates[a] = lo[a] / BrickCells;
      local[a] = lo[a] - this->BrickCoordinates[a] * BrickCells;
    }
    this->Brick = this->BrickCoordinates[0] +
      static_cast<size_t>(I.Volume.BrickCount[0]) *
        (this->BrickCoordinates[1] +
          static_cast<size_t>(I.Volume.BrickCount[1]) * this->BrickCoordinates[2]);
    this->Points = I.Volume.Bricks.data() + this->Brick * BrickValues + local[0] +
      BrickPoints * (local[1] + BrickPoints * local[2]);
    this->FirstCell = local[0] + BrickCells * (local[1] + BrickCells * local[2]);
    I.Volume.BrickVisibility(this->Brick, this->BrickCoordinates, I.Classification, this->Visible);
  }

  bool IsVisible(int cell) const { return (this->Visible[cell >> 6] >> (cell & 63)) & 1; }

  // The box of the leaf's visible cells (of the size[0] x size[1] x size[2] from its first
  // one), leaf-local cells [first, last] per axis; false when none is visible (the octree's
  // node ranges are unions of the cells' ranges: a node can be visible with no visible
  // cell). A bit per cell x + 8 y + 64 z: a word is a z slice, a byte a row along x.
  bool VisibleBox(const int size[3], int first[3], int last[3]) const
  {
    const uint64_t row = ((uint64_t(1) << size[0]) - 1) << this->Local[0];
    uint64_t slice = 0; // the leaf's rows in a slice
    for (int y = this->Local[1]; y < this->Local[1] + size[1]; ++y)
    {
      slice |= row << (BrickCells * y);
    }
    uint64_t columns = 0; // union of the slices' visible cells
    first[2] = BrickCells;
    last[2] = -1;
    for (int z = this->Local[2]; z < this->Local[2] + size[2]; ++z)
    {
      const uint64_t bits = this->Visible[z] & slice;
      if (bits)
      {
        first[2] = std::min(first[2], z);
        last[2] = z;
        columns |= bits;
      }
    }
    if (!columns)
    {
      return false;
    }
    uint64_t xs = columns | (columns >> 32); // x: the union of the rows
    xs |= xs >> 16;
    xs |= xs >> 8;
    xs &= 0xff;
    first[0] = LowestBit(xs);
    last[0] = HighestBit(xs);
    first[1] = LowestBit(columns) / BrickCells;
    last[1] = HighestBit(columns) / BrickCells;
    for (int a = 0; a < 3; ++a)
    {
      first[a] -= this->Local[a];
      last[a] -= this->Local[a];
    }
    return true;
  }

  // Asks for the points of the leaf's size[0] x size[1] x size[2] cells (a span of up to 46
  // cache lines of its brick) all at once, before its rays need them: they are then fetched
  // from memory together instead of one miss after the other as the first rays reach them,
  // which matters where the visible bricks outgrow the caches.
  void Prefetch(const int size[3]) const
  {
    constexpr int P = BrickPoints, PP = BrickPoints * BrickPoints;
    const float* last = this->Points + size[0] + P * size[1] + PP * size[2];
    for (const float* line = this->Points; line <= last; line += 64 / sizeof(float))
    {
      HOVR_PREFETCH(line);
    }
  }

  // The corners of the cell whose first point is at offset point from the leaf's first
  // point, indexed x + 2 y + 4 z.
  void Corners(int point, float v[8]) const
  {
    constexpr int P = BrickPoints, PP = BrickPoints * BrickPoints;
    const float* b = this->Points + point;
    v[0] = b[0];
    v[1] = b[1];
    v[2] = b[P];
    v[3] = b[P + 1];
    v[4] = b[PP];
    v[5] = b[PP + 1];
    v[6] = b[PP + P];
    v[7] = b[PP + P + 1];
  }

  // The cells sampled, into the frame's bits.
  void Flush(const Frame& I) const
  {
    for (int w = 0; w < BrickWords; ++w)
    {
      if (this->Sampled[w])
      {
        I.Volume.SampledBits[this->Brick * BrickWords + w].fetch_or(
          this->Sampled[w], std::memory_order_relaxed);
      }
    }
  }
};

// A pixel's ray between leaves: its chord through the volume (Rays::Chord; NaN until its
// first segment, as many pixels of a tile meet no visible leaf), its
// premultiplied RGBA so far and, for pre-integration, its last sample (scalar, index n of its
// position phase + n step: NaN when none) and the trailing half step that sample may still
// owe (its scalar, NaN when nothing is owed, and its shading: factor, highlight).
struct PixelState
{
  double Chord[2] = { std::numeric_limits<double>::quiet_NaN(), 0.0 };
  // The samples a piece draws (Rays::OwnedSamples), found with the chord.
  double Owned[2] = { -std::numeric_limits<double>::infinity(),
    std::numeric_limits<double>::infinity() };
  float RGBA[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
  double PreviousN = std::numeric_limits<double>::quiet_NaN();
  float PreviousScalar = 0.0f;
  float PendingScalar = std::numeric_limits<float>::quiet_NaN();
  float PendingShade[2] = { 0.0f, 0.0f };
};
