// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// The tiles' walk of vtkObjectOrderRayCaster (see its class description): the leaves' cells,
// their rays' segments and sample loop, and the walker of one tile. Included twice by
// vtkObjectOrderRayCaster.cxx, inside its anonymous namespace, once for SSE2 and once for AVX2
// with FMA; hence no include guard, and everything here has internal linkage.

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

#ifdef HOVR_WALKER_AVX2
// The pairs of floats at base + offsets[k], k = 0 to 3, in one vector (a 64-bit load each).
HOVR_ALWAYS_INLINE __m256 LoadPairs(const float* base, const int offsets[4])
{
  const auto pair = [base](int offset)
  { return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(base + offset)); };
  return _mm256_castsi256_ps(
    _mm256_set_m128i(_mm_unpacklo_epi64(pair(offsets[2]), pair(offsets[3])),
      _mm_unpacklo_epi64(pair(offsets[0]), pair(offsets[1]))));
}

// SegmentCells for eight positions at once, of eight rays (the AVX2 lanes of
// TileWalker::RunLanes): the same operations, fused where the AVX2 copy fuses SegmentCells'.
// Built once per leaf.
class LaneCells
{
public:
  explicit LaneCells(const LeafCells& cells)
  {
    for (int a = 0; a < 3; ++a)
    {
      this->Direction[a] = _mm256_set1_ps(cells.Direction[a]);
      this->Sign[a] = _mm256_set1_ps(cells.Sign[a]);
      this->Offset[a] = _mm256_set1_ps(cells.Offset[a]);
      this->Top[a] = _mm256_set1_ps(cells.Last[a] + 0.5f);
      this->Down[a] = _mm256_set1_epi32(-(cells.Sign[a] < 0.0f));
      this->Base[a] = _mm256_set1_epi32(cells.Base[a]);
    }
  }

  // The cells c (leaf-local) and local coordinates u = x - c of the points entry + dt
  // direction.
  void Locate(__m256 dt, const __m256 entry[3], __m256i c[3], __m256 u[3]) const
  {
    for (int a = 0; a < 3; ++a)
    {
      const __m256 x = _mm256_fmadd_ps(dt, this->Direction[a], entry[a]);
      const __m256 v = _mm256_min_ps(
        _mm256_max_ps(_mm256_fmadd_ps(this->Sign[a], x, this->Offset[a]), _mm256_setzero_ps()),
        this->Top[a]);
      c[a] = _mm256_add_epi32(
        _mm256_sub_epi32(_mm256_xor_si256(_mm256_cvttps_epi32(v), this->Down[a]), this->Down[a]),
        this->Base[a]);
      u[a] = _mm256_sub_ps(x, _mm256_cvtepi32_ps(c[a]));
    }
  }

private:
  __m256 Direction[3], Sign[3], Offset[3], Top[3];
  __m256i Down[3], Base[3];
};
#endif

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
      static_cast<size_t>(I.BrickCount[0]) *
        (this->BrickCoordinates[1] +
          static_cast<size_t>(I.BrickCount[1]) * this->BrickCoordinates[2]);
    this->Points = I.Bricks.data() + this->Brick * BrickValues + local[0] +
      BrickPoints * (local[1] + BrickPoints * local[2]);
    this->FirstCell = local[0] + BrickCells * (local[1] + BrickCells * local[2]);
    I.BrickVisibility(this->Brick, this->BrickCoordinates, this->Visible);
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
        I.SampledBits[this->Brick * BrickWords + w].fetch_or(
          this->Sampled[w], std::memory_order_relaxed);
      }
    }
  }
};

// A pixel's ray between leaves: its chord through the volume (Frame::Chord; NaN until its
// first segment, as many pixels of a tile meet no visible leaf), its
// premultiplied RGBA so far and, for pre-integration, its last sample (scalar, index n of its
// position phase + n step: NaN when none) and the trailing half step that sample may still
// owe (its scalar, NaN when nothing is owed, and its shading: factor, highlight).
struct PixelState
{
  double Chord[2] = { std::numeric_limits<double>::quiet_NaN(), 0.0 };
  float RGBA[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
  double PreviousN = std::numeric_limits<double>::quiet_NaN();
  float PreviousScalar = 0.0f;
  float PendingScalar = std::numeric_limits<float>::quiet_NaN();
  float PendingShade[2] = { 0.0f, 0.0f };
};

// One tile's walk of the octree: front to back, skipping transparent, off-tile and hidden
// nodes, ray casting every pixel ray through each remaining leaf.
class TileWalker
{
public:
  const Frame& I;
  const vtkMinMaxOctree* Octree;
  float* Image; // W x H RGBA
  // The tile's pixels, row by row, written to the image after the walk: a leaf's rays
  // touch one small block instead of rows of whole-image arrays a power of two apart, which
  // fall in the same few cache sets and evict each other.
  std::vector<PixelState> Pixels;
  int TileWidth = 0;
  void (TileWalker::*LeafFunction)(int, const int*, const int*) = nullptr;
  // The rays' direction (grid index per unit of t, the same for every ray of a parallel
  // view) in float.
  float Direction[3];
  vtkHierarchicalOcclusionMap Occlusion;
  int Clip[4];  // tile pixels [x0, x1] x [y0, y1]
  int First[3]; // child visited first per axis: 0 (low) when the rays go up that axis
  bool Render = true;
  bool Removal = true;
  float S0, InvStep, LastEntry;    // the table's mapping, in float for the sample loop
  float SegmentScale, SegmentLast; // the pre-integration table's mapping
  double PerStep;                  // 1 / step: products per pixel and segment, not divisions
  // After the walk of a tile: the trailing half steps still owed (rays whose last visible
  // sample was followed by transparent cells only); then the tile into the image.
  void Finish()
  {
    const int height = this->Clip[3] - this->Clip[2] + 1;
    for (int ly = 0; ly < height; ++ly)
    {
      for (int lx = 0; lx < this->TileWidth; ++lx)
      {
        PixelState& state = this->Pixels[lx + static_cast<size_t>(this->TileWidth) * ly];
        if (this->I.Preintegrated && state.PendingScalar == state.PendingScalar &&
          !this->Occlusion.IsPixelOpaque(lx, ly))
        {
          alignas(16) float piece[4];
          this->ScalarPiece(state.PendingScalar, 0.5 * this->I.Step, piece);
          Composite<1>(
            state.RGBA, piece, state.PendingShade[0], state.PendingShade[1], this->I.Threshold);
        }
        const size_t p = static_cast<size_t>(this->Clip[0] + lx) +
          static_cast<size_t>(this->I.Width) * (this->Clip[2] + ly);
        std::copy(state.RGBA, state.RGBA + 4, this->Image + 4 * p);
      }
    }
  }

  // Front-to-back "over" of a piece of ray (premultiplied colour and opacity, 4 floats),
  // lit by (shade, highlight) (see Frame::Lighting), into the premultiplied RGBA acc; true
  // when acc becomes opaque (its alpha reaches threshold). With SSE2 the four channels take
  // one vector each, with the same operations per channel as the scalar loop.
  template <int Shading>
  static bool Composite(float acc[4],
    const float piece[4],
    float shade,
    float highlight,
    float threshold)
  {
    // No test for a transparent piece: it adds exactly nothing (its colour is at most its
    // opacity, 0), and the branch on it is hard to predict.
    const float alpha = piece[3];
    const float transmittance = 1.0f - acc[3];
#ifdef HOVR_SSE2
    // The colour lit, then at most alpha: (shade, 1) and (highlight alpha, 0) leave the
    // alpha channel as it is.
    __m128 c = _mm_loadu_ps(piece);
    if (Shading)
    {
      c = _mm_add_ps(_mm_mul_ps(c, _mm_setr_ps(shade, shade, shade, 1.0f)),
        _mm_setr_ps(highlight * alpha, highlight * alpha, highlight * alpha, 0.0f));
    }
    c = _mm_min_ps(c, _mm_set1_ps(alpha));
    _mm_storeu_ps(acc, _mm_add_ps(_mm_loadu_ps(acc), _mm_mul_ps(_mm_set1_ps(transmittance), c)));
#else
    for (int ch = 0; ch < 3; ++ch)
    {
      acc[ch] += transmittance *
        std::min(Shading ? piece[ch] * shade + highlight * alpha : piece[ch], alpha);
    }
    acc[3] += transmittance * alpha;
#endif
    return acc[3] >= threshold;
  }

  // A piece of length `length` point-sampled at the table entry a0 + f (alpha of one step).
  static void PointPiece(const float* a0, float f, double length, double step, float piece[4])
  {
    const float full = a0[3] + f * (a0[7] - a0[3]);
    // alpha = 1 - (1 - full)^(length / step); the two lengths most pieces have (a whole step
    // and half of one) without the logarithm and exponential (to 1e-12 of the exponent). The
    // other lengths (a ray's first and last pieces, one per ray entering through a visible
    // face) take float logf and expf, which cost much less than double log1p and expm1; the
    // absolute error of alpha stays within a few float ulps of 1, far below the sampling error.
    const double ratio = length / step;
    float alpha;
    if (std::abs(ratio - 1.0) <= 1e-12)
    {
      alpha = full;
    }
    else if (std::abs(ratio - 0.5) <= 1e-12)
    {
      alpha = full / (1.0f + std::sqrt(1.0f - full)); // 1 - sqrt(1 - full), without cancellation
    }
    else
    {
      alpha = 1.0f - std::exp(std::log(1.0f - full) * static_cast<float>(ratio));
    }
    piece[3] = alpha;
    for (int ch = 0; ch < 3; ++ch)
    {
      piece[ch] = alpha * (a0[ch] + f * (a0[ch + 4] - a0[ch]));
    }
  }
  vtkIdType Nodes = 0, Samples = 0, Cells = 0;

  TileWalker(const Frame& internals, const vtkMinMaxOctree* octree)
    : I(internals)
    , Octree(octree)
    , Removal(internals.Removal)
    , S0(static_cast<float>(internals.S0))
    , InvStep(static_cast<float>(internals.InvStep))
    , LastEntry(static_cast<float>(internals.Entries - 1))
    , SegmentScale(static_cast<float>(internals.SegmentInvStep))
    , SegmentLast(static_cast<float>(internals.SegmentEntries - 1))
    , PerStep(1.0 / internals.Step)
  {
    for (int a = 0; a < 3; ++a)
    {
      this->First[a] = internals.D[a] >= 0.0 ? 0 : 1;
      this->Direction[a] = static_cast<float>(internals.D[a]);
    }
    // The leaf's rendering specialized for the classification and the shading.
    using Function = decltype(&TileWalker::Leaf<true, 0>);
    const Function functions[2][3] = {
      { &TileWalker::Leaf<false, 0>, &TileWalker::Leaf<false, 1>, &TileWalker::Leaf<false, 2> },
      { &TileWalker::Leaf<true, 0>, &TileWalker::Leaf<true, 1>, &TileWalker::Leaf<true, 2> }
    };
    this->LeafFunction = functions[internals.Preintegrated ? 1 : 0][internals.Shading];
  }

  void Walk(const int clip[4])
  {
    std::copy(clip, clip + 4, this->Clip);
    this->TileWidth = clip[1] - clip[0] + 1;
    this->Occlusion.Initialize(this->TileWidth, clip[3] - clip[2] + 1);
    if (this->Render)
    {
      this->Pixels.assign(static_cast<size_t>(this->TileWidth) * (clip[3] - clip[2] + 1), {});
    }
    this->Node(this->Octree->GetNumberOfLevels(), 0, 0, 0);
    if (this->Render)
    {
      this->Finish();
    }
  }

  void Node(int level, int i, int j, int k)
  {
    ++this->Nodes;
    const int index[3] = { i, j, k };
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = index[a] << level;
      hi[a] = std::min((index[a] + 1) << level, this->I.Cells[a]);
    }
    // Nodes: the stored range first (one lookup), then the screen tests. Cells: the screen
    // tests first, so that hidden cells never load their 8 corners.
    float range[2];
    if (level > 0)
    {
      this->Octree->GetNodeRange(level, i, j, k, range);
      if (!this->I.Visible(range[0], range[1]))
      {
        return;
      }
    }
    int rect[4];
    if (!this->I.Rectangle(lo, hi, this->Clip, rect))
    {
      return;
    }
    if (this->Removal &&
      this->Occlusion.IsRectangleOpaque(rect[0] - this->Clip[0],
        rect[2] - this->Clip[2],
        rect[1] - this->Clip[0],
        rect[3] - this->Clip[2]))
    {
      return;
    }
    if (this->Render && level <= this->I.LeafLevel)
    {
      (this->*(this->LeafFunction))(level, index, rect);
      return;
    }
    if (level == 0)
    {
      // Counting only (ComputeNonTransparentCells): a cell with a NaN corner is transparent
      // (the interpolant is NaN in the whole cell).
      float corners[8], cornerLo, cornerHi;
      if (this->I.Corners(i, j, k, corners, cornerLo, cornerHi) &&
        this->I.Visible(cornerLo, cornerHi))
      {
        ++this->Cells;
      }
      return;
    }
    int size[3];
    this->Octree->GetLevelSize(level - 1, size);
    for (int dz = 0; dz < 2; ++dz)
    {
      const int ck = 2 * k + (dz ^ this->First[2]);
      if (ck >= size[2])
      {
        continue;
      }
      for (int dy = 0; dy < 2; ++dy)
      {
        const int cj = 2 * j + (dy ^ this->First[1]);
        if (cj >= size[1])
        {
          continue;
        }
        for (int dx = 0; dx < 2; ++dx)
        {
          const int ci = 2 * i + (dx ^ this->First[0]);
          if (ci < size[0])
          {
            this->Node(level - 1, ci, cj, ck);
          }
        }
      }
    }
  }

  // Section 3 at the scale of a leaf of the octree (2^LeafLevel cells per edge, fewer at the
  // far faces), while its voxels are in cache: every pixel ray through the leaf is sampled at
  // its global sample positions inside the leaf's segment [tin, tout). A sample interpolates
  // the 8 corners of the cell it falls in; a cell whose corner range is transparent (or that
  // has a NaN corner) takes no sample. Leaves of one cell are
  // the paper's per-cell rendering.
  template <bool Preintegrated, int Shading>
  void Leaf(int level, const int index[3], const int leafRect[4])
  {
    const auto& I = this->I;
    int lo[3], size[3];
    int far[3];
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = index[a] << level;
      size[a] = std::min((index[a] + 1) << level, I.Cells[a]) - lo[a];
      far[a] = lo[a] + size[a];
    }
    // The leaf in its brick, and the box of its visible cells: the rays are clipped to it,
    // since the positions outside it fall in transparent cells: fewer positions and pixels
    // are tested.
    LeafView leaf(I, lo);
    int first[3], last[3];
    if (!leaf.VisibleBox(size, first, last))
    {
      return;
    }
    // The planes each ray meets first and last per axis (by the sign of the direction): the
    // leaf's own where the box reaches its face, so that the leaves sharing a face give a
    // sample on it the same t and it belongs to one of them only; inside the leaf, the box's
    // face moved a 64th of a cell outwards, far more than the rounding of t and of a
    // position's cell, so that the positions clipped away lie in transparent cells.
    constexpr double margin = 1.0 / 64.0;
    double boxLo[3], boxHi[3], nearPlane[3], farPlane[3];
    for (int a = 0; a < 3; ++a)
    {
      boxLo[a] = first[a] == 0 ? lo[a] : lo[a] + first[a] - margin;
      boxHi[a] = last[a] + 1 == size[a] ? far[a] : lo[a] + last[a] + 1 + margin;
      nearPlane[a] = I.D[a] > 0.0 ? boxLo[a] : boxHi[a];
      farPlane[a] = I.D[a] > 0.0 ? boxHi[a] : boxLo[a];
    }
    int rect[4]; // the box's pixels, within the leaf's
    if (!I.Rectangle(boxLo, boxHi, leafRect, rect) ||
      (this->Removal &&
        this->Occlusion.IsRectangleOpaque(rect[0] - this->Clip[0],
          rect[2] - this->Clip[2],
          rect[1] - this->Clip[0],
          rect[3] - this->Clip[2])))
    {
      return;
    }
    leaf.Prefetch(size);
    const LeafCells cells(this->Direction, size);
    SegmentCells locator(cells);
#ifdef HOVR_WALKER_AVX2
    const LaneCells laneCells(cells);
    Lanes lanes;
#endif
    const double step = I.Step;
    const double interleave = I.Interleaved ? 0.5 * step : 0.0; // the odd pixels' phase
    vtkIdType samples = 0; // added to this->Samples at the end (not per sample:
                           // the member may alias the image for the compiler)
    // A pixel ray's part [tin, tout) of the leaf, from its sample phase + n step on; entry:
    // the ray at tin, leaf-local. Sampled now, or (AVX2, unshaded) queued for eight lanes.
    auto sample = [&](int px, int py, double phase, double n, double tin, double tout,
                    const float entry[3])
    {
      const int lx = px - this->Clip[0], ly = py - this->Clip[2];
      PixelState& state = this->Pixels[lx + static_cast<size_t>(this->TileWidth) * ly];
      if (state.Chord[0] != state.Chord[0])
      {
        // (At the pixel's first segment rather than for every pixel of the tile before its
        // walk: many pixels of a tile meet no visible leaf and never need their chord.)
        I.Chord(px, py, state.Chord[0], state.Chord[1]);
      }
#ifdef HOVR_WALKER_AVX2
      if (Shading == 0)
      {
        const int l = lanes.Count++;
        lanes.Phase[l] = phase;
        lanes.N[l] = n;
        lanes.Tin[l] = tin;
        lanes.Tout[l] = tout;
        for (int a = 0; a < 3; ++a)
        {
          lanes.Entry[a][l] = entry[a];
        }
        lanes.States[l] = &state;
        lanes.Pixels[l][0] = lx;
        lanes.Pixels[l][1] = ly;
        if (lanes.Count == 8)
        {
          this->RunLanes<Preintegrated>(lanes, laneCells, leaf, samples);
        }
        return;
      }
#endif
      if (this->Segment<Preintegrated, Shading>(
            state, phase, n, tin, tout, entry, locator, lo, leaf, samples))
      {
        this->Occlusion.SetPixelOpaque(lx, ly);
      }
    };
#ifdef HOVR_WALKER_AVX2
    if (!I.Still[0] && !I.Still[1] && !I.Still[2])
    {
      this->VectorRays(rect, lo, nearPlane, farPlane, interleave, sample);
    }
    else
#endif
    {
      for (int py = rect[2]; py <= rect[3]; ++py)
      {
        const double row[3] = { I.O[0] + py * I.EY[0], I.O[1] + py * I.EY[1],
          I.O[2] + py * I.EY[2] };
        for (int px = rect[0]; px <= rect[1]; ++px)
        {
          if (this->Occlusion.IsPixelOpaque(px - this->Clip[0], py - this->Clip[2]))
          {
            continue;
          }
          double o[3];
          double tin = 0.0, tout = std::numeric_limits<double>::infinity();
          bool inside = true;
          for (int a = 0; a < 3; ++a)
          {
            o[a] = row[a] + px * I.EX[a];
            if (I.Still[a])
            {
              // A ray in a cell plane belongs to the cell above it (the last cell keeps its
              // far face), so no sample is taken twice.
              inside = inside && o[a] >= lo[a] &&
                (o[a] < far[a] || (far[a] == I.Cells[a] && o[a] <= far[a]));
              continue;
            }
            // The same expression for a plane in both leaves that share it: equal t.
            tin = std::max(tin, (nearPlane[a] - o[a]) * I.InvD[a]);
            tout = std::min(tout, (farPlane[a] - o[a]) * I.InvD[a]);
          }
          if (!inside || !(tin < tout))
          {
            continue;
          }
          // (A product, not a branch: the checkerboard alternates every pixel.)
          const double phase = ((px + py) & 1) * interleave;
          // The first sample position at or after tin, whatever the product rounds to (a
          // sample exactly on a face belongs to the leaf behind it, and to no other); the
          // truncation is the ceiling or one less (tin - phase > -step).
          double n = static_cast<double>(static_cast<long long>((tin - phase) * this->PerStep));
          while (phase + n * step < tin)
          {
            n += 1.0;
          }
          while (phase + (n - 1.0) * step >= tin)
          {
            n -= 1.0;
          }
          if (!(phase + n * step < tout))
          {
            continue;
          }
          // Leaf-local coordinates in float, where they are small: the ray at tin.
          float entry[3];
          for (int a = 0; a < 3; ++a)
          {
            entry[a] = static_cast<float>(o[a] + tin * I.D[a] - lo[a]);
          }
          sample(px, py, phase, n, tin, tout, entry);
        }
      }
    }
#ifdef HOVR_WALKER_AVX2
    if (lanes.Count > 0)
    {
      this->RunLanes<Preintegrated>(lanes, laneCells, leaf, samples);
    }
#endif
    this->Samples += samples;
    leaf.Flush(I);
  }

#ifdef HOVR_WALKER_AVX2
  // Leaf's pixel rays four at a time, for views along no grid plane: per ray the same
  // operations as Leaf's loop (fused where this copy fuses them), so the same segments,
  // passed to sample in the same order.
  template <typename Sample>
  HOVR_ALWAYS_INLINE void VectorRays(const int rect[4],
    const int lo[3],
    const double nearPlane[3],
    const double farPlane[3],
    double interleave,
    Sample& sample) const
  {
    const auto& I = this->I;
    const __m256d step = _mm256_set1_pd(I.Step), perStep = _mm256_set1_pd(this->PerStep);
    const __m256d one = _mm256_set1_pd(1.0);
    const __m256d infinity = _mm256_set1_pd(std::numeric_limits<double>::infinity());
    const __m256d offsets = _mm256_setr_pd(0.0, 1.0, 2.0, 3.0);
    // The checkerboard's phases of four pixels from an even and from an odd one.
    const __m256d phases[2] = { _mm256_setr_pd(0.0, interleave, 0.0, interleave),
      _mm256_setr_pd(interleave, 0.0, interleave, 0.0) };
    __m256d nearP[3], farP[3], invD[3], ex[3], d[3], low[3];
    for (int a = 0; a < 3; ++a)
    {
      nearP[a] = _mm256_set1_pd(nearPlane[a]);
      farP[a] = _mm256_set1_pd(farPlane[a]);
      invD[a] = _mm256_set1_pd(I.InvD[a]);
      ex[a] = _mm256_set1_pd(I.EX[a]);
      d[a] = _mm256_set1_pd(I.D[a]);
      low[a] = _mm256_set1_pd(lo[a]);
    }
    alignas(32) double tins[4], touts[4], ns[4], phaseOf[4];
    alignas(16) float entries[3][4];
    for (int py = rect[2]; py <= rect[3]; ++py)
    {
      const int ly = py - this->Clip[2];
      __m256d row[3];
      for (int a = 0; a < 3; ++a)
      {
        row[a] = _mm256_set1_pd(I.O[a] + py * I.EY[a]);
      }
      for (int px0 = rect[0]; px0 <= rect[1]; px0 += 4)
      {
        unsigned todo = 0;
        for (int l = 0; l < 4 && px0 + l <= rect[1]; ++l)
        {
          todo |= this->Occlusion.IsPixelOpaque(px0 + l - this->Clip[0], ly) ? 0u : 1u << l;
        }
        if (!todo)
        {
          continue;
        }
        const __m256d px = _mm256_add_pd(_mm256_set1_pd(px0), offsets);
        __m256d o[3];
        __m256d tin = _mm256_setzero_pd(), tout = infinity;
        for (int a = 0; a < 3; ++a)
        {
          o[a] = _mm256_fmadd_pd(px, ex[a], row[a]);
          // std::max(tin, x) and std::min(tout, x), as Leaf's loop.
          tin = _mm256_max_pd(_mm256_mul_pd(_mm256_sub_pd(nearP[a], o[a]), invD[a]), tin);
          tout = _mm256_min_pd(_mm256_mul_pd(_mm256_sub_pd(farP[a], o[a]), invD[a]), tout);
        }
        todo &= static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(tin, tout, _CMP_LT_OQ)));
        if (!todo)
        {
          continue;
        }
        const __m256d phase = phases[(px0 + py) & 1];
        const __m256d lanes = _mm256_castsi256_pd(_mm256_cmpgt_epi64(
          _mm256_and_si256(_mm256_set1_epi64x(todo), _mm256_setr_epi64x(1, 2, 4, 8)),
          _mm256_setzero_si256()));
        __m256d n = _mm256_round_pd(_mm256_mul_pd(_mm256_sub_pd(tin, phase), perStep),
          _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
        for (;;)
        {
          const __m256d up =
            _mm256_and_pd(_mm256_cmp_pd(_mm256_fmadd_pd(n, step, phase), tin, _CMP_LT_OQ), lanes);
          if (_mm256_testz_pd(up, up))
          {
            break;
          }
          n = _mm256_add_pd(n, _mm256_and_pd(up, one));
        }
        for (;;)
        {
          const __m256d down = _mm256_and_pd(
            _mm256_cmp_pd(_mm256_fmadd_pd(_mm256_sub_pd(n, one), step, phase), tin, _CMP_GE_OQ),
            lanes);
          if (_mm256_testz_pd(down, down))
          {
            break;
          }
          n = _mm256_sub_pd(n, _mm256_and_pd(down, one));
        }
        todo &= static_cast<unsigned>(
          _mm256_movemask_pd(_mm256_cmp_pd(_mm256_fmadd_pd(n, step, phase), tout, _CMP_LT_OQ)));
        if (!todo)
        {
          continue;
        }
        for (int a = 0; a < 3; ++a)
        {
          _mm_store_ps(
            entries[a], _mm256_cvtpd_ps(_mm256_sub_pd(_mm256_fmadd_pd(tin, d[a], o[a]), low[a])));
        }
        _mm256_store_pd(tins, tin);
        _mm256_store_pd(touts, tout);
        _mm256_store_pd(ns, n);
        _mm256_store_pd(phaseOf, phase);
        do
        {
          const int l = __builtin_ctz(todo);
          todo &= todo - 1;
          const float entry[3] = { entries[0][l], entries[1][l], entries[2][l] };
          sample(px0 + l, py, phaseOf[l], ns[l], tins[l], touts[l], entry);
        } while (todo);
      }
    }
  }

#endif

#ifdef HOVR_WALKER_AVX2
  // Up to eight pixel rays of a leaf, sampled together (below).
  struct Lanes
  {
    alignas(32) double Phase[8];
    alignas(32) double N[8];
    alignas(32) double Tin[8];
    alignas(32) double Tout[8];
    alignas(32) float Entry[3][8];
    PixelState* States[8];
    int Pixels[8][2];
    int Count = 0;
  };

  // The segments of up to eight pixel rays through a leaf (unshaded), one AVX2 lane each,
  // in step: each round finds the next sample position of every ray, its cell and whether
  // it is visible, loads the 8 corners and interpolates, and places the scalars in the
  // segment table, eight at a time; then the rays that took a sample composite it, one after
  // the other (Take), in their own order. The operations per lane are Segment's, the same
  // float operations in the same order (fused where the AVX2 copy of Segment fuses them), so
  // the image is the same.
  template <bool Preintegrated>
  void RunLanes(Lanes& lanes, const LaneCells& leafCells, LeafView& leaf, vtkIdType& samples)
  {
    // A local copy, which the stores of the loop cannot alias: the constants stay in
    // registers rather than being read again through the reference.
    const LaneCells cells = leafCells;
    const auto& I = this->I;
    const int count = lanes.Count;
    lanes.Count = 0;
    Ray rays[8];
    for (int l = 0; l < count; ++l)
    {
      this->BeginRay<Preintegrated>(rays[l], *lanes.States[l], lanes.Phase[l]);
    }
    for (int l = count; l < 8; ++l)
    {
      // Unused lanes: no sample position (t < tout never holds), in the leaf's first cell.
      lanes.Phase[l] = lanes.N[l] = lanes.Tin[l] = 0.0;
      lanes.Tout[l] = -std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a)
      {
        lanes.Entry[a][l] = 0.0f;
      }
    }
    const __m256d step = _mm256_set1_pd(I.Step), one = _mm256_set1_pd(1.0);
    const __m256d phase[2] = { _mm256_load_pd(lanes.Phase), _mm256_load_pd(lanes.Phase + 4) };
    const __m256d tin[2] = { _mm256_load_pd(lanes.Tin), _mm256_load_pd(lanes.Tin + 4) };
    const __m256d tout[2] = { _mm256_load_pd(lanes.Tout), _mm256_load_pd(lanes.Tout + 4) };
    __m256d n[2] = { _mm256_load_pd(lanes.N), _mm256_load_pd(lanes.N + 4) };
    __m256 entry[3];
    for (int a = 0; a < 3; ++a)
    {
      entry[a] = _mm256_load_ps(lanes.Entry[a]);
    }
    const __m256i firstCell = _mm256_set1_epi32(leaf.FirstCell);
    const __m256i visible[2] = { _mm256_loadu_si256(reinterpret_cast<const __m256i*>(leaf.Visible)),
      _mm256_loadu_si256(reinterpret_cast<const __m256i*>(leaf.Visible + 4)) };
    constexpr int P = BrickPoints, PP = BrickPoints * BrickPoints;
    const float* points = leaf.Points;
    unsigned live = (1u << count) - 1, opaque = 0;
    alignas(32) double t[8], ns[8];
    alignas(32) float scalar[8], fraction[8];
    alignas(32) int keys[8], index[8];
    for (;;)
    {
      __m256d tt[2];
      unsigned inside = 0;
      for (int h = 0; h < 2; ++h)
      {
        tt[h] = _mm256_fmadd_pd(n[h], step, phase[h]);
        inside |= static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(tt[h], tout[h], _CMP_LT_OQ)))
          << (4 * h);
      }
      live &= inside;
      if (!live)
      {
        break;
      }
      const __m256 dt = _mm256_set_m128(_mm256_cvtpd_ps(_mm256_sub_pd(tt[1], tin[1])),
        _mm256_cvtpd_ps(_mm256_sub_pd(tt[0], tin[0])));
      __m256i c[3];
      __m256 u[3];
      cells.Locate(dt, entry, c, u);
      const __m256i key = _mm256_add_epi32(firstCell,
        _mm256_add_epi32(c[0],
          _mm256_slli_epi32(_mm256_add_epi32(c[1], _mm256_slli_epi32(c[2], 3)), 3)));
      // The cell's bit among the brick's visible ones, whose 16 32-bit words two registers
      // hold: a permutation of each and a blend by the sign of the word index shifted so
      // that its fourth bit is the sign (shorter than a gather's latency).
      const __m256i word = _mm256_srli_epi32(key, 5);
      const __m256i bit = _mm256_and_si256(
        _mm256_srlv_epi32(
          _mm256_castps_si256(_mm256_blendv_ps(
            _mm256_castsi256_ps(_mm256_permutevar8x32_epi32(visible[0], word)),
            _mm256_castsi256_ps(_mm256_permutevar8x32_epi32(visible[1], word)),
            _mm256_castsi256_ps(_mm256_slli_epi32(word, 28)))),
          _mm256_and_si256(key, _mm256_set1_epi32(31))),
        _mm256_set1_epi32(1));
      unsigned taken = live &
        static_cast<unsigned>(
          _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(bit, _mm256_set1_epi32(1)))));
      if (taken)
      {
        // The cell's first point c0 + P (c1 + P c2), P = 9, and its 8 corners.
        const __m256i row = _mm256_add_epi32(c[1], _mm256_add_epi32(_mm256_slli_epi32(c[2], 3), c[2]));
        const __m256i point =
          _mm256_add_epi32(c[0], _mm256_add_epi32(_mm256_slli_epi32(row, 3), row));
        // The corners in pairs along x (a 64-bit load each, half the loads of loading them
        // one by one): 4 rows (y, z) for lanes 0-3 and 4 for lanes 4-7, split into the
        // corners of lanes 0 1 4 5 2 3 6 7 (the pairs' order), in which the trilinear
        // interpolation runs. Loads and shuffles rather than AVX2 gathers, which are slow on
        // common x86 cores.
        alignas(32) int pointOf[8];
        _mm256_store_si256(reinterpret_cast<__m256i*>(pointOf), point);
        __m256 v[8];
        for (int r = 0; r < 4; ++r)
        {
          const float* corners = points + (r & 1) * P + (r >> 1) * PP;
          const __m256 low = LoadPairs(corners, pointOf);
          const __m256 high = LoadPairs(corners, pointOf + 4);
          v[2 * r] = _mm256_shuffle_ps(low, high, _MM_SHUFFLE(2, 0, 2, 0));
          v[2 * r + 1] = _mm256_shuffle_ps(low, high, _MM_SHUFFLE(3, 1, 3, 1));
        }
        __m256 w[3]; // u in the pairs' lane order
        for (int a = 0; a < 3; ++a)
        {
          w[a] = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(u[a]), 0xD8));
        }
        // Trilinear, fused as its scalar form is in this copy, then back in lane order.
        const __m256 x0 = _mm256_fmadd_ps(w[0], _mm256_sub_ps(v[1], v[0]), v[0]);
        const __m256 x1 = _mm256_fmadd_ps(w[0], _mm256_sub_ps(v[3], v[2]), v[2]);
        const __m256 x2 = _mm256_fmadd_ps(w[0], _mm256_sub_ps(v[5], v[4]), v[4]);
        const __m256 x3 = _mm256_fmadd_ps(w[0], _mm256_sub_ps(v[7], v[6]), v[6]);
        const __m256 y0 = _mm256_fmadd_ps(w[1], _mm256_sub_ps(x1, x0), x0);
        const __m256 y1 = _mm256_fmadd_ps(w[1], _mm256_sub_ps(x3, x2), x2);
        const __m256 sv = _mm256_castpd_ps(_mm256_permute4x64_pd(
          _mm256_castps_pd(_mm256_fmadd_ps(w[2], _mm256_sub_ps(y1, y0), y0)), 0xD8));
        _mm256_store_ps(scalar, sv);
        _mm256_store_si256(reinterpret_cast<__m256i*>(keys), key);
        _mm256_store_pd(t, tt[0]);
        _mm256_store_pd(t + 4, tt[1]);
        _mm256_store_pd(ns, n[0]);
        _mm256_store_pd(ns + 4, n[1]);
        if (Preintegrated)
        {
          // SegmentPlace, eight at once (max and min in std::max and std::min's order).
          __m256 e = _mm256_mul_ps(
            _mm256_sub_ps(sv, _mm256_set1_ps(this->S0)), _mm256_set1_ps(this->SegmentScale));
          e = _mm256_min_ps(
            _mm256_set1_ps(this->SegmentLast), _mm256_max_ps(_mm256_setzero_ps(), e));
          const __m256i i0 = _mm256_min_epi32(
            _mm256_cvttps_epi32(e), _mm256_set1_epi32(I.SegmentEntries - 2));
          _mm256_store_si256(reinterpret_cast<__m256i*>(index), i0);
          _mm256_store_ps(fraction, _mm256_sub_ps(e, _mm256_cvtepi32_ps(i0)));
        }
        samples += __builtin_popcount(taken);
        do
        {
          const int l = __builtin_ctz(taken);
          taken &= taken - 1;
          const int k = keys[l];
          leaf.Sampled[k >> 6] |= uint64_t(1) << (k & 63);
          TablePlace place;
          if (Preintegrated)
          {
            place.Index = index[l];
            place.Fraction = fraction[l];
          }
          if (this->Take<Preintegrated, 0>(rays[l], scalar[l], place, ns[l], t[l], 1.0f, 0.0f))
          {
            live &= ~(1u << l);
            opaque |= 1u << l;
          }
        } while (taken);
      }
      n[0] = _mm256_add_pd(n[0], one);
      n[1] = _mm256_add_pd(n[1], one);
    }
    for (int l = 0; l < count; ++l)
    {
      this->EndRay<Preintegrated>(rays[l], *lanes.States[l]);
      if ((opaque >> l) & 1)
      {
        this->Occlusion.SetPixelOpaque(lanes.Pixels[l][0], lanes.Pixels[l][1]);
      }
    }
  }
#endif

  // The classification-table coordinate of a scalar (entries linear in between).
  float Entry(float s) const
  {
    return std::min(std::max((s - this->S0) * this->InvStep, 0.0f), this->LastEntry);
  }

  // A piece of ray of one step, point-sampled at scalar s: PointPiece for that length, in
  // float (without the length's ratio to the step and its tests).
  void StepPiece(float s, float piece[4]) const
  {
    const float e = this->Entry(s);
    const int e0 = std::min(static_cast<int>(e), this->I.Entries - 2);
    const float f = e - e0;
    const float* a0 = this->I.Table.data() + 4 * e0;
#ifdef HOVR_SSE2
    const __m128 low = _mm_loadu_ps(a0), high = _mm_loadu_ps(a0 + 4);
    const __m128 v = _mm_add_ps(low, _mm_mul_ps(_mm_set1_ps(f), _mm_sub_ps(high, low)));
    // The colour times the alpha, the alpha kept: v (alpha, alpha, alpha, 1).
    const __m128 alphaOne =
      _mm_move_ss(_mm_shuffle_ps(v, v, _MM_SHUFFLE(3, 3, 3, 3)), _mm_set_ss(1.0f));
    _mm_storeu_ps(
      piece, _mm_mul_ps(v, _mm_shuffle_ps(alphaOne, alphaOne, _MM_SHUFFLE(0, 1, 1, 1))));
#else
    const float alpha = a0[3] + f * (a0[7] - a0[3]);
    for (int ch = 0; ch < 3; ++ch)
    {
      piece[ch] = (a0[ch] + f * (a0[ch + 4] - a0[ch])) * alpha;
    }
    piece[3] = alpha;
#endif
  }

  // A piece of ray of length `length`, point-sampled at scalar s.
  void ScalarPiece(float s, double length, float piece[4]) const
  {
    const float e = this->Entry(s);
    const int e0 = std::min(static_cast<int>(e), this->I.Entries - 2);
    PointPiece(this->I.Table.data() + 4 * e0, e - e0, length, this->I.Step, piece);
  }

  // A scalar's place in the pre-integration table: the entry below it and the fraction to
  // the next.
  struct TablePlace
  {
    int Index = 0;
    float Fraction = 0.0f;
  };

  // A pixel's ray while a leaf's samples are composited into it: its PixelState held in
  // locals, the chord's ends and the sample indices far enough from them (Inner) that their
  // samples are surely neither its first (t - step < te) nor its last (t + step >= tx), with a
  // margin of a step for rounding: there Take has its common case without testing those ends.
  // Pre-integration: the previous sample (scalar, its place in the segment table, index n:
  // NaN when none) and the trailing half step it may still owe (its scalar, NaN when nothing
  // is owed, and its shading).
  struct Ray
  {
    float Acc[4];
    double Chord[2];
    double Inner[2];
    double PreviousN;
    float PreviousScalar, PendingScalar, PendingShade[2];
    TablePlace PreviousPlace;
  };

  template <bool Preintegrated>
  HOVR_ALWAYS_INLINE void BeginRay(Ray& ray, const PixelState& state, double phase) const
  {
    std::copy(state.RGBA, state.RGBA + 4, ray.Acc);
    ray.Chord[0] = state.Chord[0];
    ray.Chord[1] = state.Chord[1];
    ray.Inner[0] = (state.Chord[0] - phase) * this->PerStep + 2.0;
    ray.Inner[1] = (state.Chord[1] - phase) * this->PerStep - 2.0;
    if (Preintegrated)
    {
      ray.PreviousScalar = state.PreviousScalar;
      ray.PreviousN = state.PreviousN;
      ray.PendingScalar = state.PendingScalar;
      ray.PendingShade[0] = state.PendingShade[0];
      ray.PendingShade[1] = state.PendingShade[1];
      // The previous sample's place in the segment table, kept rather than found again for
      // each segment: the same value, computed once per sample rather than twice.
      ray.PreviousPlace = this->SegmentPlace(ray.PreviousScalar);
    }
  }

  template <bool Preintegrated>
  HOVR_ALWAYS_INLINE static void EndRay(const Ray& ray, PixelState& state)
  {
    std::copy(ray.Acc, ray.Acc + 4, state.RGBA);
    if (Preintegrated)
    {
      state.PreviousScalar = ray.PreviousScalar;
      state.PreviousN = ray.PreviousN;
      state.PendingScalar = ray.PendingScalar;
      state.PendingShade[0] = ray.PendingShade[0];
      state.PendingShade[1] = ray.PendingShade[1];
    }
  }

  // Composites the sample of scalar s (its segment-table place, for pre-integration) at
  // t = phase + n step, lit by (shade, highlight), into the ray; true when the ray becomes
  // opaque.
  template <bool Preintegrated, int Shading>
  HOVR_ALWAYS_INLINE bool Take(
    Ray& ray, float s, TablePlace place, double n, double t, float shade, float highlight) const
  {
    const double step = this->I.Step;
    const double te = ray.Chord[0], tx = ray.Chord[1];
    const float threshold = this->I.Threshold;
    alignas(16) float piece[4];
    bool opaque = false;
    if (Preintegrated)
    {
      // Pre-integrated segments between consecutive samples (Engel et al.'s table, the
      // project's vtkFirstOrderPreIntegrationTable); point-sampled pieces from the chord's
      // entry (or after a gap of transparent cells) to the first sample and from the last
      // one to the exit.
      const bool joined = ray.PreviousN + 1.0 == n; // false when there is none (NaN)
      if (HOVR_LIKELY(joined && n < ray.Inner[1]))
      {
        // Most samples: the segment from the previous one, and this one owes its trailing
        // half step until the next joins it. (One test here rather than the general case's
        // tests of the chord's end and the gap.)
        this->SegmentPiece(ray.PreviousPlace, place, piece);
        opaque = Composite<Shading>(ray.Acc, piece, shade, highlight, threshold);
        ray.PendingScalar = s;
      }
      else
      {
        const bool last = t + step >= tx;
        if (!joined && ray.PendingScalar == ray.PendingScalar)
        {
          // After a gap of transparent cells: the previous sample's trailing half step.
          this->ScalarPiece(ray.PendingScalar, 0.5 * step, piece);
          opaque =
            Composite<Shading>(ray.Acc, piece, ray.PendingShade[0], ray.PendingShade[1], threshold);
        }
        if (!opaque)
        {
          if (joined)
          {
            this->SegmentPiece(ray.PreviousPlace, place, piece);
          }
          else
          {
            this->ScalarPiece(s, t - (t - step < te ? te : t - 0.5 * step), piece);
          }
          opaque = Composite<Shading>(ray.Acc, piece, shade, highlight, threshold);
        }
        if (!opaque && last)
        {
          this->ScalarPiece(s, tx - t, piece);
          opaque = Composite<Shading>(ray.Acc, piece, shade, highlight, threshold);
        }
        // Until the next sample joins it by a segment, this one owes its trailing half
        // step (composited after a gap, or at the end of the walk).
        ray.PendingScalar = last ? std::numeric_limits<float>::quiet_NaN() : s;
      }
      ray.PreviousScalar = s;
      ray.PreviousPlace = place;
      ray.PreviousN = n;
      ray.PendingShade[0] = shade;
      ray.PendingShade[1] = highlight;
    }
    else
    {
      // Each sample stands for the part of the ray closer to it than to its neighbours, the
      // first one from the box entry on and the last one up to the exit (midpoint rule with
      // the ends included), so no part of the chord is left out or counted twice whatever
      // the phase.
      const bool first = !(n > ray.Inner[0]) && t - step < te; // the chord's first sample
      const bool last = !(n < ray.Inner[1]) && t + step >= tx; // and its last
      if (HOVR_LIKELY(!first && !last))
      {
        this->StepPiece(s, piece); // a whole step around the sample, as most are
      }
      else
      {
        const double from = first ? te : t - 0.5 * step;
        const double to = last ? tx : t + 0.5 * step;
        this->ScalarPiece(s, to - from, piece);
      }
      opaque = Composite<Shading>(ray.Acc, piece, shade, highlight, threshold);
    }
    return opaque;
  }

  // The part [tin, tout) of a pixel's ray (its state) in the leaf at lo, from its sample
  // phase + n step on; entry: the ray at tin, leaf-local (its direction is Direction). Each
  // sample position finds its cell from its leaf-local coordinates (cells), in the leaf's
  // small float coordinates, and is taken when that cell is visible. (Rather than a walk cell
  // by cell: no branch per cell crossed, whose outcome the branch predictor misses often, and
  // fewer instructions on small cells.)
  // Specialized for the classification and the shading, so the loop holds only the code the
  // scene needs. True when the pixel became opaque.
  template <bool Preintegrated, int Shading>
  bool Segment(PixelState& state,
    double phase,
    double n,
    double tin,
    double tout,
    const float entry[3],
    SegmentCells& locator,
    const int lo[3],
    LeafView& leaf,
    vtkIdType& samples)
  {
    const double step = this->I.Step;
    Ray ray;
    this->BeginRay<Preintegrated>(ray, state, phase);
    double t = phase + n * step;
    float corners[8], gradients[3][8], lit[2][8];
    int loaded = -1; // the bit of the cell whose shading data are loaded
    bool opaque = false;
    locator.Start(entry);
    for (; t < tout; n += 1.0, t = phase + n * step)
    {
      alignas(16) int c[4];
      alignas(16) float u[4];
      locator.Locate(static_cast<float>(t - tin), c, u);
      const int key = leaf.FirstCell + c[0] + BrickCells * (c[1] + BrickCells * c[2]);
      if (!leaf.IsVisible(key))
      {
        continue; // a transparent cell (or one with a NaN corner) takes no sample
      }
      // The corners at every sample, not when the cell changes: 8 loads from the brick in
      // cache cost less than a branch the predictor misses about every other sample (a cell
      // holds about 1/step samples). The shading data are too costly for that.
      leaf.Corners(c[0] + BrickPoints * (c[1] + BrickPoints * c[2]), corners);
      leaf.Sampled[key >> 6] |= uint64_t(1) << (key & 63); // the cell's data made a sample
      if (Shading && key != loaded)
      {
        loaded = key;
        const int cell[3] = { lo[0] + c[0], lo[1] + c[1], lo[2] + c[2] };
        this->CellShading(cell, gradients, lit);
      }
      const float s = Trilinear(corners, u);
      ++samples;
      float shade = 1.0f, highlight = 0.0f;
      if (Shading == 1)
      {
        float g[3];
        for (int a = 0; a < 3; ++a)
        {
          g[a] = Trilinear(gradients[a], u);
        }
        this->I.Lighting(this->I.LightCosine(g), shade, highlight);
      }
      else if (Shading == 2)
      {
        shade = Trilinear(lit[0], u);
        highlight = Trilinear(lit[1], u);
      }
      const TablePlace place = Preintegrated ? this->SegmentPlace(s) : TablePlace();
      if (this->Take<Preintegrated, Shading>(ray, s, place, n, t, shade, highlight))
      {
        opaque = true;
        break;
      }
    }
    this->EndRay<Preintegrated>(ray, state);
    return opaque;
  }

  TablePlace SegmentPlace(float scalar) const
  {
    float e = (scalar - this->S0) * this->SegmentScale;
    e = std::min(std::max(e, 0.0f), this->SegmentLast);
    TablePlace place;
    place.Index = std::min(static_cast<int>(e), this->I.SegmentEntries - 2);
    place.Fraction = e - place.Index;
    return place;
  }

  // The pre-integrated segment between consecutive samples at table places front and back
  // (the first-order table, bilinear). A sample's place serves as the back of one segment
  // and the front of the next.
  void SegmentPiece(const TablePlace& frontPlace, const TablePlace& backPlace, float piece[4]) const
  {
    const auto& I = this->I;
    const int i0 = frontPlace.Index, j0 = backPlace.Index;
    const float fi = frontPlace.Fraction, fj = backPlace.Fraction;
    const float* e00 = I.Segments + 4 * (i0 + static_cast<size_t>(I.SegmentEntries) * j0);
    const float* e01 = e00 + 4 * I.SegmentEntries;
#ifdef HOVR_SSE2
    const __m128 a = _mm_loadu_ps(e00), b = _mm_loadu_ps(e00 + 4);
    const __m128 c = _mm_loadu_ps(e01), d = _mm_loadu_ps(e01 + 4);
    const __m128 lower = _mm_add_ps(a, _mm_mul_ps(_mm_set1_ps(fi), _mm_sub_ps(b, a)));
    const __m128 upper = _mm_add_ps(c, _mm_mul_ps(_mm_set1_ps(fi), _mm_sub_ps(d, c)));
    _mm_storeu_ps(piece, _mm_add_ps(lower, _mm_mul_ps(_mm_set1_ps(fj), _mm_sub_ps(upper, lower))));
#else
    for (int ch = 0; ch < 4; ++ch)
    {
      const float lower = e00[ch] + fi * (e00[ch + 4] - e00[ch]);
      const float upper = e01[ch] + fi * (e01[ch + 4] - e01[ch]);
      piece[ch] = lower + fj * (upper - lower);
    }
#endif
  }

  // Shading data of the 8 corners of a cell: gradients (post-shading, interpolated per sample)
  // or the reflectance of their quantized normals (pre-shading, section 4.3.2: the vertices
  // are shaded, the shading interpolated).
  void CellShading(const int c[3], float gradients[3][8], float lit[2][8]) const
  {
    const auto& I = this->I;
    for (int v = 0; I.Shading && v < 8; ++v)
    {
      const int x = c[0] + (v & 1), y = c[1] + ((v >> 1) & 1), z = c[2] + (v >> 2);
      if (I.Shading == 1)
      {
        float g[3];
        I.Gradient(x, y, z, g);
        for (int a = 0; a < 3; ++a)
        {
          gradients[a][v] = g[a];
        }
      }
      else
      {
        const float* r = I.Reflectance.data() + 2 * I.Directions[I.Address(x, y, z)];
        lit[0][v] = r[0];
        lit[1][v] = r[1];
      }
    }
  }
};
