// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// The sample loop of vtkObjectOrderRayCaster's tile walk: a pixel ray's samples in a leaf,
// their classification and shading, and their compositing into the ray. Included by
// vtkObjectOrderRayCasterTiles.cxx once per copy of the walk (SSE2, and AVX2 with FMA),
// inside its anonymous namespace; hence no include guard, and everything here has internal
// linkage.

// The samples of the pixel rays' segments through a leaf, composited front to back into the
// rays (see vtkObjectOrderRayCaster's class description). The tile walker (TileWalker) finds
// the segments; the table mappings are held in float for the sample loop.
class RaySampler
{
public:
  const Frame& I;
  float S0, InvStep, LastEntry;    // the table's mapping, in float for the sample loop
  float SegmentScale, SegmentLast; // the pre-integration table's mapping
  double PerStep;                  // 1 / step: products per pixel and segment, not divisions

  explicit RaySampler(const Frame& frame)
    : I(frame)
    , S0(static_cast<float>(frame.Classification.S0))
    , InvStep(static_cast<float>(frame.Classification.InvStep))
    , LastEntry(static_cast<float>(frame.Classification.Entries - 1))
    , SegmentScale(static_cast<float>(frame.Classification.SegmentInvStep))
    , SegmentLast(static_cast<float>(frame.Classification.SegmentEntries - 1))
    , PerStep(1.0 / frame.Step)
  {
  }

  // Front-to-back "over" of a piece of ray (premultiplied colour and opacity, 4 floats),
  // lit by (shade, highlight) (see vtkObjectOrderRayCasterShading::Lighting), into the
  // premultiplied RGBA acc; true when acc becomes opaque (its alpha reaches threshold). With SSE2
  // the four channels take one vector each, with the same operations per channel as the scalar
  // loop.
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
    const int e0 = std::min(static_cast<int>(e), this->I.Classification.Entries - 2);
    const float f = e - e0;
    const float* a0 = this->I.Classification.Table.data() + 4 * e0;
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
    const int e0 = std::min(static_cast<int>(e), this->I.Classification.Entries - 2);
    PointPiece(this->I.Classification.Table.data() + 4 * e0, e - e0, length, this->I.Step, piece);
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
    double Owned[2];
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
    ray.Owned[0] = state.Owned[0];
    ray.Owned[1] = state.Owned[1];
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
  HOVR_ALWAYS_INLINE bool
  Take(Ray& ray, float s, TablePlace place, double n, double t, float shade, float highlight) const
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
      // On a piece, what a sample's step composites is drawn by the piece that owns the
      // sample, and the trailing half step a sample owes by the piece that owns that one.
      const bool owned = n >= ray.Owned[0] && n < ray.Owned[1];
      if (HOVR_LIKELY(joined && n < ray.Inner[1] && owned))
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
        if (!joined && ray.PendingScalar == ray.PendingScalar && ray.PreviousN >= ray.Owned[0] &&
          ray.PreviousN < ray.Owned[1])
        {
          // After a gap of transparent cells: the previous sample's trailing half step.
          this->ScalarPiece(ray.PendingScalar, 0.5 * step, piece);
          opaque =
            Composite<Shading>(ray.Acc, piece, ray.PendingShade[0], ray.PendingShade[1], threshold);
        }
        if (!opaque && owned)
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
        if (!opaque && owned && last)
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
      if (n >= ray.Owned[0] && n < ray.Owned[1])
      {
        opaque = Composite<Shading>(ray.Acc, piece, shade, highlight, threshold);
      }
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
        this->I.Shading.Lighting(this->I.Shading.LightCosine(g), shade, highlight);
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
    place.Index = std::min(static_cast<int>(e), this->I.Classification.SegmentEntries - 2);
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
    const float* e00 = I.Classification.Segments +
      4 * (i0 + static_cast<size_t>(I.Classification.SegmentEntries) * j0);
    const float* e01 = e00 + 4 * I.Classification.SegmentEntries;
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
    for (int v = 0; I.Shading.Mode && v < 8; ++v)
    {
      const int x = c[0] + (v & 1), y = c[1] + ((v >> 1) & 1), z = c[2] + (v >> 2);
      if (I.Shading.Mode == 1)
      {
        float g[3];
        I.Volume.Gradient(x, y, z, g);
        for (int a = 0; a < 3; ++a)
        {
          gradients[a][v] = g[a];
        }
      }
      else
      {
        const float* r =
          I.Shading.Reflectance.data() + 2 * I.Shading.Directions[I.Volume.Address(x, y, z)];
        lit[0][v] = r[0];
        lit[1][v] = r[1];
      }
    }
  }
};
