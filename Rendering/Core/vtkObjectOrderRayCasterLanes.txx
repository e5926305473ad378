// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// The eight-lane sample loop of vtkObjectOrderRayCaster's tile walk, in the AVX2 copy only:
// the unshaded rays of a leaf sampled eight at a time, one vector lane each (positions, cells,
// corners and scalars as vectors), so that eight rays share each instruction; and the first
// sample positions of the walker's four-ray loop (TileWalker::VectorRays). Included by
// vtkObjectOrderRayCasterTiles.cxx inside its anonymous namespace; hence no include guard, and
// everything here has internal linkage.
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

// SegmentCells for eight positions at once, of eight rays (the lanes of LaneSampler): the same
// operations, fused where the AVX2 copy fuses SegmentCells'. Built once per leaf.
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

// The indices n of the first sample positions phase + n step at or after tin of four rays (the
// lanes set in todo), whatever the product rounds to, as TileWalker::ScalarRays finds them one
// ray at a time.
HOVR_ALWAYS_INLINE __m256d
FirstSamples(__m256d tin, __m256d phase, unsigned todo, __m256d step, __m256d perStep)
{
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256d lanes = _mm256_castsi256_pd(
    _mm256_cmpgt_epi64(_mm256_and_si256(_mm256_set1_epi64x(todo), _mm256_setr_epi64x(1, 2, 4, 8)),
      _mm256_setzero_si256()));
  __m256d n = _mm256_round_pd(
    _mm256_mul_pd(_mm256_sub_pd(tin, phase), perStep), _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
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
      _mm256_cmp_pd(_mm256_fmadd_pd(_mm256_sub_pd(n, one), step, phase), tin, _CMP_GE_OQ), lanes);
    if (_mm256_testz_pd(down, down))
    {
      break;
    }
    n = _mm256_sub_pd(n, _mm256_and_pd(down, one));
  }
  return n;
}

// The lanes whose cell (key: its bit x + 8 y + 64 z in the brick) is visible, as a mask. The
// cell's bit among the brick's visible ones, whose 16 32-bit words two registers hold: a
// permutation of each and a blend by the sign of the word index shifted so that its fourth bit
// is the sign (shorter than a gather's latency).
HOVR_ALWAYS_INLINE unsigned VisibleLanes(__m256i key, const __m256i visible[2])
{
  const __m256i word = _mm256_srli_epi32(key, 5);
  const __m256i bit = _mm256_and_si256(
    _mm256_srlv_epi32(_mm256_castps_si256(_mm256_blendv_ps(
                        _mm256_castsi256_ps(_mm256_permutevar8x32_epi32(visible[0], word)),
                        _mm256_castsi256_ps(_mm256_permutevar8x32_epi32(visible[1], word)),
                        _mm256_castsi256_ps(_mm256_slli_epi32(word, 28)))),
      _mm256_and_si256(key, _mm256_set1_epi32(31))),
    _mm256_set1_epi32(1));
  return static_cast<unsigned>(
    _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(bit, _mm256_set1_epi32(1)))));
}

// The scalars of eight lanes: the trilinear interpolation at local coordinates u of the cells
// c (leaf-local) of the leaf whose first point is points.
HOVR_ALWAYS_INLINE __m256 Interpolate(const float* points, const __m256i c[3], const __m256 u[3])
{
  constexpr int P = BrickPoints, PP = BrickPoints * BrickPoints;
  // The cells' first points c0 + P (c1 + P c2), P = 9, and their 8 corners.
  const __m256i row = _mm256_add_epi32(c[1], _mm256_add_epi32(_mm256_slli_epi32(c[2], 3), c[2]));
  const __m256i point = _mm256_add_epi32(c[0], _mm256_add_epi32(_mm256_slli_epi32(row, 3), row));
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
  return _mm256_castpd_ps(_mm256_permute4x64_pd(
    _mm256_castps_pd(_mm256_fmadd_ps(w[2], _mm256_sub_ps(y1, y0), y0)), 0xD8));
}

// RaySampler::SegmentPlace of eight scalars: the segment-table entries below them, and the
// fractions to the next (max and min in std::max and std::min's order).
HOVR_ALWAYS_INLINE void SegmentPlaces(__m256 sv,
  const RaySampler& sampler,
  int index[8],
  float fraction[8])
{
  __m256 e = _mm256_mul_ps(
    _mm256_sub_ps(sv, _mm256_set1_ps(sampler.S0)), _mm256_set1_ps(sampler.SegmentScale));
  e = _mm256_min_ps(_mm256_set1_ps(sampler.SegmentLast), _mm256_max_ps(_mm256_setzero_ps(), e));
  const __m256i i0 = _mm256_min_epi32(
    _mm256_cvttps_epi32(e), _mm256_set1_epi32(sampler.I.Classification.SegmentEntries - 2));
  _mm256_store_si256(reinterpret_cast<__m256i*>(index), i0);
  _mm256_store_ps(fraction, _mm256_sub_ps(e, _mm256_cvtepi32_ps(i0)));
}

// Up to eight pixel rays of a leaf (unshaded), queued by the walker and sampled together: the
// segments of the rays, one AVX2 lane each, in step: each round finds the next sample position
// of every ray, its cell and whether it is visible, loads the 8 corners and interpolates, and
// places the scalars in the segment table, eight at a time; then the rays that took a sample
// composite it, one after the other (RaySampler::Take), in their own order. The operations per
// lane are RaySampler::Segment's, the same float operations in the same order (fused where the
// AVX2 copy of Segment fuses them), so the image is the same.
template <bool Preintegrated>
class LaneSampler
{
public:
  LaneSampler(const RaySampler& sampler,
    const LeafCells& cells,
    LeafView& leaf,
    vtkHierarchicalOcclusionMap& occlusion)
    : Sampler(sampler)
    , Cells(cells)
    , Leaf(leaf)
    , Occlusion(occlusion)
  {
  }

  // The part [tin, tout) of the ray of tile pixel (lx, ly) (its state), from its sample
  // phase + n step on; entry: the ray at tin, leaf-local. Sampled with seven others, or at
  // Flush.
  void Add(PixelState& state,
    int lx,
    int ly,
    double phase,
    double n,
    double tin,
    double tout,
    const float entry[3],
    vtkIdType& samples)
  {
    const int l = this->Count++;
    this->Phase[l] = phase;
    this->N[l] = n;
    this->Tin[l] = tin;
    this->Tout[l] = tout;
    for (int a = 0; a < 3; ++a)
    {
      this->Entry[a][l] = entry[a];
    }
    this->States[l] = &state;
    this->Pixels[l][0] = lx;
    this->Pixels[l][1] = ly;
    if (this->Count == 8)
    {
      this->Run(samples);
    }
  }

  // Samples the rays still queued.
  void Flush(vtkIdType& samples)
  {
    if (this->Count > 0)
    {
      this->Run(samples);
    }
  }

private:
  const RaySampler& Sampler;
  const LaneCells Cells;
  LeafView& Leaf;
  vtkHierarchicalOcclusionMap& Occlusion;
  alignas(32) double Phase[8];
  alignas(32) double N[8];
  alignas(32) double Tin[8];
  alignas(32) double Tout[8];
  alignas(32) float Entry[3][8];
  PixelState* States[8];
  int Pixels[8][2];
  int Count = 0;

  // The queued rays' segments, sampled together (see the class description).
  void Run(vtkIdType& samples)
  {
    // A local copy, which the stores of the loop cannot alias: the constants stay in
    // registers rather than being read again through the reference.
    const LaneCells cells = this->Cells;
    const RaySampler& sampler = this->Sampler;
    const auto& I = sampler.I;
    LeafView& leaf = this->Leaf;
    const int count = this->Count;
    this->Count = 0;
    RaySampler::Ray rays[8];
    for (int l = 0; l < count; ++l)
    {
      sampler.BeginRay<Preintegrated>(rays[l], *this->States[l], this->Phase[l]);
    }
    for (int l = count; l < 8; ++l)
    {
      // Unused lanes: no sample position (t < tout never holds), in the leaf's first cell.
      this->Phase[l] = this->N[l] = this->Tin[l] = 0.0;
      this->Tout[l] = -std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a)
      {
        this->Entry[a][l] = 0.0f;
      }
    }
    const __m256d step = _mm256_set1_pd(I.Step), one = _mm256_set1_pd(1.0);
    const __m256d phase[2] = { _mm256_load_pd(this->Phase), _mm256_load_pd(this->Phase + 4) };
    const __m256d tin[2] = { _mm256_load_pd(this->Tin), _mm256_load_pd(this->Tin + 4) };
    const __m256d tout[2] = { _mm256_load_pd(this->Tout), _mm256_load_pd(this->Tout + 4) };
    __m256d n[2] = { _mm256_load_pd(this->N), _mm256_load_pd(this->N + 4) };
    __m256 entry[3];
    for (int a = 0; a < 3; ++a)
    {
      entry[a] = _mm256_load_ps(this->Entry[a]);
    }
    const __m256i firstCell = _mm256_set1_epi32(leaf.FirstCell);
    const __m256i visible[2] = { _mm256_loadu_si256(reinterpret_cast<const __m256i*>(leaf.Visible)),
      _mm256_loadu_si256(reinterpret_cast<const __m256i*>(leaf.Visible + 4)) };
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
        inside |=
          static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(tt[h], tout[h], _CMP_LT_OQ)))
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
        _mm256_add_epi32(
          c[0], _mm256_slli_epi32(_mm256_add_epi32(c[1], _mm256_slli_epi32(c[2], 3)), 3)));
      unsigned taken = live & VisibleLanes(key, visible);
      if (taken)
      {
        const __m256 sv = Interpolate(points, c, u);
        _mm256_store_ps(scalar, sv);
        _mm256_store_si256(reinterpret_cast<__m256i*>(keys), key);
        _mm256_store_pd(t, tt[0]);
        _mm256_store_pd(t + 4, tt[1]);
        _mm256_store_pd(ns, n[0]);
        _mm256_store_pd(ns + 4, n[1]);
        if (Preintegrated)
        {
          SegmentPlaces(sv, sampler, index, fraction);
        }
        samples += __builtin_popcount(taken);
        do
        {
          const int l = __builtin_ctz(taken);
          taken &= taken - 1;
          const int k = keys[l];
          leaf.Sampled[k >> 6] |= uint64_t(1) << (k & 63);
          RaySampler::TablePlace place;
          if (Preintegrated)
          {
            place.Index = index[l];
            place.Fraction = fraction[l];
          }
          if (sampler.Take<Preintegrated, 0>(rays[l], scalar[l], place, ns[l], t[l], 1.0f, 0.0f))
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
      sampler.EndRay<Preintegrated>(rays[l], *this->States[l]);
      if ((opaque >> l) & 1)
      {
        this->Occlusion.SetPixelOpaque(this->Pixels[l][0], this->Pixels[l][1]);
      }
    }
  }
};
#endif
