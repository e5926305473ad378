// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// The tile walker of vtkObjectOrderRayCaster (see its class description): one tile's
// front-to-back walk of the octree with its occlusion map, and the pixel rays' segments through
// each leaf it renders. Included by vtkObjectOrderRayCasterTiles.cxx once per copy of the walk
// (SSE2, and AVX2 with FMA), inside its anonymous namespace, after the leaves
// (vtkObjectOrderRayCasterLeaf.txx), the sample loop (vtkObjectOrderRayCasterSamples.txx) and,
// in the AVX2 copy, the eight-lane sample loop (vtkObjectOrderRayCasterLanes.txx); hence no
// include guard, and everything here has internal linkage.

// One tile's walk of the octree: front to back, skipping transparent, off-tile and hidden
// nodes, ray casting every pixel ray through each remaining leaf.
class TileWalker : public RaySampler
{
public:
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
  // The walk's octree nodes visited, samples taken and (counting only) non-transparent cells.
  vtkIdType Nodes = 0, Samples = 0, Cells = 0;

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
        if (this->I.Classification.Preintegrated && state.PendingScalar == state.PendingScalar &&
          !this->Occlusion.IsPixelOpaque(lx, ly) && state.PreviousN >= state.Owned[0] &&
          state.PreviousN < state.Owned[1])
        {
          alignas(16) float piece[4];
          this->ScalarPiece(state.PendingScalar, 0.5 * this->I.Step, piece);
          Composite<1>(
            state.RGBA, piece, state.PendingShade[0], state.PendingShade[1], this->I.Threshold);
        }
        const size_t p = static_cast<size_t>(this->Clip[0] + lx) +
          static_cast<size_t>(this->I.Rays.Width) * (this->Clip[2] + ly);
        std::copy(state.RGBA, state.RGBA + 4, this->Image + 4 * p);
      }
    }
  }

  TileWalker(const Frame& internals, const vtkMinMaxOctree* octree)
    : RaySampler(internals)
    , Octree(octree)
    , Removal(internals.Removal)
  {
    for (int a = 0; a < 3; ++a)
    {
      this->First[a] = internals.Rays.D[a] >= 0.0 ? 0 : 1;
      this->Direction[a] = static_cast<float>(internals.Rays.D[a]);
    }
    // The leaf's rendering specialized for the classification and the shading.
    using Function = decltype(&TileWalker::Leaf<true, 0>);
    const Function functions[2][3] = {
      { &TileWalker::Leaf<false, 0>, &TileWalker::Leaf<false, 1>, &TileWalker::Leaf<false, 2> },
      { &TileWalker::Leaf<true, 0>, &TileWalker::Leaf<true, 1>, &TileWalker::Leaf<true, 2> }
    };
    this->LeafFunction =
      functions[internals.Classification.Preintegrated ? 1 : 0][internals.Shading.Mode];
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
      hi[a] = std::min((index[a] + 1) << level, this->I.Volume.Cells[a]);
    }
    // Nodes: the stored range first (one lookup), then the screen tests. Cells: the screen
    // tests first, so that hidden cells never load their 8 corners.
    float range[2];
    if (level > 0)
    {
      this->Octree->GetNodeRange(level, i, j, k, range);
      if (!this->I.Classification.Visible(range[0], range[1]))
      {
        return;
      }
    }
    int rect[4];
    if (!this->I.Rays.Rectangle(lo, hi, this->Clip, rect))
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
      if (this->I.Volume.Corners(i, j, k, corners, cornerLo, cornerHi) &&
        this->I.Classification.Visible(cornerLo, cornerHi))
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
      size[a] = std::min((index[a] + 1) << level, I.Volume.Cells[a]) - lo[a];
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
      nearPlane[a] = I.Rays.D[a] > 0.0 ? boxLo[a] : boxHi[a];
      farPlane[a] = I.Rays.D[a] > 0.0 ? boxHi[a] : boxLo[a];
    }
    int rect[4]; // the box's pixels, within the leaf's
    if (!I.Rays.Rectangle(boxLo, boxHi, leafRect, rect) ||
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
    LaneSampler<Preintegrated> lanes(*this, cells, leaf, this->Occlusion);
#endif
    const double interleave = I.Interleaved ? 0.5 * I.Step : 0.0; // the odd pixels' phase
    vtkIdType samples = 0; // added to this->Samples at the end (not per sample:
                           // the member may alias the image for the compiler)
    // A pixel ray's part [tin, tout) of the leaf, from its sample phase + n step on; entry:
    // the ray at tin, leaf-local. Sampled now, or (AVX2, unshaded) queued for eight lanes.
    auto sample =
      [&](int px, int py, double phase, double n, double tin, double tout, const float entry[3])
    {
      const int lx = px - this->Clip[0], ly = py - this->Clip[2];
      PixelState& state = this->Pixels[lx + static_cast<size_t>(this->TileWidth) * ly];
      if (state.Chord[0] != state.Chord[0])
      {
        // (At the pixel's first segment rather than for every pixel of the tile before its
        // walk: many pixels of a tile meet no visible leaf and never need their chord.)
        I.Rays.Chord(px, py, state.Chord[0], state.Chord[1]);
        I.Rays.OwnedSamples(px, py, phase, state.Owned);
      }
#ifdef HOVR_WALKER_AVX2
      if (Shading == 0)
      {
        lanes.Add(state, lx, ly, phase, n, tin, tout, entry, samples);
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
    if (!I.Rays.Still[0] && !I.Rays.Still[1] && !I.Rays.Still[2])
    {
      this->VectorRays(rect, lo, nearPlane, farPlane, interleave, sample);
    }
    else
#endif
    {
      this->ScalarRays(rect, lo, far, nearPlane, farPlane, interleave, sample);
    }
#ifdef HOVR_WALKER_AVX2
    lanes.Flush(samples);
#endif
    this->Samples += samples;
    leaf.Flush(I);
  }

  // Leaf's pixel rays one at a time: each ray's segment [tin, tout) between the planes it
  // meets first and last per axis (nearPlane, farPlane; a ray along a grid plane is in the
  // leaf or not) and its first sample position in it, passed to sample.
  template <typename Sample>
  HOVR_ALWAYS_INLINE void ScalarRays(const int rect[4],
    const int lo[3],
    const int far[3],
    const double nearPlane[3],
    const double farPlane[3],
    double interleave,
    Sample& sample) const
  {
    const auto& I = this->I;
    const double step = I.Step;
    for (int py = rect[2]; py <= rect[3]; ++py)
    {
      const double row[3] = { I.Rays.O[0] + py * I.Rays.EY[0],
        I.Rays.O[1] + py * I.Rays.EY[1],
        I.Rays.O[2] + py * I.Rays.EY[2] };
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
          o[a] = row[a] + px * I.Rays.EX[a];
          if (I.Rays.Still[a])
          {
            // A ray in a cell plane belongs to the cell above it (the last cell keeps its
            // far face), so no sample is taken twice.
            inside = inside && o[a] >= lo[a] &&
              (o[a] < far[a] || (far[a] == I.Volume.Cells[a] && o[a] <= far[a]));
            continue;
          }
          // The same expression for a plane in both leaves that share it: equal t.
          tin = std::max(tin, (nearPlane[a] - o[a]) * I.Rays.InvD[a]);
          tout = std::min(tout, (farPlane[a] - o[a]) * I.Rays.InvD[a]);
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
          entry[a] = static_cast<float>(o[a] + tin * I.Rays.D[a] - lo[a]);
        }
        sample(px, py, phase, n, tin, tout, entry);
      }
    }
  }

#ifdef HOVR_WALKER_AVX2
  // Leaf's pixel rays four at a time, for views along no grid plane: per ray the same
  // operations as ScalarRays (fused where this copy fuses them), so the same segments,
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
      invD[a] = _mm256_set1_pd(I.Rays.InvD[a]);
      ex[a] = _mm256_set1_pd(I.Rays.EX[a]);
      d[a] = _mm256_set1_pd(I.Rays.D[a]);
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
        row[a] = _mm256_set1_pd(I.Rays.O[a] + py * I.Rays.EY[a]);
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
          // std::max(tin, x) and std::min(tout, x), as ScalarRays.
          tin = _mm256_max_pd(_mm256_mul_pd(_mm256_sub_pd(nearP[a], o[a]), invD[a]), tin);
          tout = _mm256_min_pd(_mm256_mul_pd(_mm256_sub_pd(farP[a], o[a]), invD[a]), tout);
        }
        todo &= static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(tin, tout, _CMP_LT_OQ)));
        if (!todo)
        {
          continue;
        }
        const __m256d phase = phases[(px0 + py) & 1];
        const __m256d n = FirstSamples(tin, phase, todo, step, perStep);
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
};
