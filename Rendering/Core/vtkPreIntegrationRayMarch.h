// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkPreIntegrationRayMarch
 * @brief   one ray through the trilinear field as the pre-integration GLSL composites it
 *
 * The CPU mirror, in double, of hovrPreIntegration1.glsl and hovrPreIntegration2.glsl:
 * samples one step apart from the point where the ray enters the box of the volume's points,
 * the first a full step inside; first order composites the segment between consecutive
 * samples and the partial last one up to the exit; second order the slab of two steps
 * (front, middle, back) and what remains as a shorter slab through its front, midpoint and
 * end; a ray stops once its opacity exceeds the threshold. What a segment or slab contributes
 * comes from a Pieces policy:
 *   - TablePieces reads a table as linear texture filtering does (entries at texel centres,
 *     clamp-to-edge) and scales partial pieces as the GLSL does (colour per opacity kept,
 *     optical depth scaled by the length);
 *   - ExactPieces integrates the model scalar path (linear or quadratic, Eq. 2) through the
 *     transfer function, with pieces no wider than a scalar step, in double.
 * Shaded first order (Guetat et al. 2010, as hovrPreIntegrationShading.glsl) takes the normals
 * at both ends of each segment (Grid::Normal: VTK's normalised central-difference gradient),
 * shaded second order those at the front, middle and back of each slab:
 *   - ShadedTablePieces reads the moment layers of the table and lights them with
 *     vtkVolumeShadingModel::ShadeSegment() (a slab: once per half, between the normals at
 *     its ends), as the GLSL does;
 *   - ShadedExactPieces integrates the segment model (linear scalar, nlerp normal; a slab:
 *     quadratic scalar, nlerp over each half) point by point with
 *     vtkVolumeShadingModel::ShadePoint(): the segment-model reference R2.
 * vtkPreIntegrationRayCaster renders camera images with it; vtkPreIntegrationTableSizer
 * measures candidate tables on random rays with it.
 */
#ifndef vtkPreIntegrationRayMarch_h
#define vtkPreIntegrationRayMarch_h

#include "vtkFloatArray.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkType.h"
#include "vtkVolumeScalarView.h"
#include "vtkVolumeShadingModel.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

class vtkPreIntegrationRayMarch
{
public:
  // The volume: point values (x fastest) on a grid of Dims points, positions in 0-based
  // continuous grid index.
  struct Grid
  {
    vtkVolumeScalarView Values;
    int Dims[3] = { 2, 2, 2 };

    // Trilinear value at p (clamped to the box of the points).
    double Sample(const double p[3]) const
    {
      int cell[3];
      double w[3];
      for (int a = 0; a < 3; ++a)
      {
        const double x = std::min(std::max(p[a], 0.0), this->Dims[a] - 1.0);
        cell[a] = std::min(static_cast<int>(x), this->Dims[a] - 2);
        w[a] = x - cell[a];
      }
      const vtkIdType sy = this->Dims[0];
      const vtkIdType sz = sy * this->Dims[1];
      double v[8];
      this->Values.GetCellCorners(cell[0] + sy * cell[1] + sz * cell[2], sy, sz, v);
      const double c00 = v[0] + w[0] * (v[1] - v[0]);
      const double c10 = v[2] + w[0] * (v[3] - v[2]);
      const double c01 = v[4] + w[0] * (v[5] - v[4]);
      const double c11 = v[6] + w[0] * (v[7] - v[6]);
      const double c0 = c00 + w[1] * (c10 - c00);
      const double c1 = c01 + w[1] * (c11 - c01);
      return c0 + w[2] * (c1 - c0);
    }

    // Shading: the normal at p (clamped to the box), normalised (zero where it vanishes or is
    // not finite), in world units. With Normals (3 per point, world units), the trilinear
    // interpolation of those vectors. Else the gradient, in index space along each axis a:
    //   - CellStepGradients (VTK 9.1's GPU ray caster, computeGradient): the difference of the
    //     trilinear field one texture cell step (1 / (Dims[a] - 1) of the texture, that is
    //     Dims[a] / (Dims[a] - 1) points) either side of p, the positions clamped to the box as
    //     the texture's clamp-to-edge clamps them;
    //   - otherwise vtkVolumeReferenceIntegrator's: the trilinear interpolation of per-point
    //     differences of the neighbours one point away, one-sided at the faces (the central
    //     difference of the trilinear field one point either side, clamped);
    // then taken to world units by M^T, M = WorldToIndex the 3 x 3 world-to-index matrix (row
    // major): divided by the spacing for an axis-aligned grid, as VTK divides it.
    const double* Normals = nullptr;
    bool CellStepGradients = true;
    double WorldToIndex[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };

    void Normal(const double p[3], double n[3]) const
    {
      double g[3] = { 0, 0, 0 };
      if (this->Normals || !this->CellStepGradients)
      {
        int cell[3];
        double w[3];
        for (int a = 0; a < 3; ++a)
        {
          const double x = std::min(std::max(p[a], 0.0), this->Dims[a] - 1.0);
          cell[a] = std::min(static_cast<int>(x), this->Dims[a] - 2);
          w[a] = x - cell[a];
        }
        const vtkIdType stride[3] = {
          1, this->Dims[0], static_cast<vtkIdType>(this->Dims[0]) * this->Dims[1]
        };
        for (int c = 0; c < 8; ++c)
        {
          const int q[3] = {
            cell[0] + (c & 1), cell[1] + ((c >> 1) & 1), cell[2] + ((c >> 2) & 1)
          };
          const double weight = ((c & 1) ? w[0] : 1.0 - w[0]) * ((c & 2) ? w[1] : 1.0 - w[1]) *
            ((c & 4) ? w[2] : 1.0 - w[2]);
          const vtkIdType base = q[0] + q[1] * stride[1] + q[2] * stride[2];
          for (int a = 0; a < 3; ++a)
          {
            double d;
            if (this->Normals)
            {
              d = this->Normals[3 * base + a];
            }
            else
            {
              const vtkIdType up = q[a] + 1 < this->Dims[a] ? stride[a] : 0;
              const vtkIdType down = q[a] > 0 ? stride[a] : 0;
              d = this->Values[base + up] - this->Values[base - down];
            }
            g[a] += weight * d;
          }
        }
      }
      else
      {
        for (int a = 0; a < 3; ++a)
        {
          const double reach = this->Dims[a] / (this->Dims[a] - 1.0);
          double ahead[3] = { p[0], p[1], p[2] }, behind[3] = { p[0], p[1], p[2] };
          ahead[a] += reach;
          behind[a] -= reach;
          g[a] = this->Sample(ahead) - this->Sample(behind);
        }
      }
      if (!this->Normals)
      {
        const double index[3] = { g[0], g[1], g[2] };
        const double* m = this->WorldToIndex;
        for (int a = 0; a < 3; ++a)
        {
          g[a] = m[a] * index[0] + m[3 + a] * index[1] + m[6 + a] * index[2];
        }
      }
      Normalize(g, n);
    }

    // v / |v|, zero where |v| vanishes or is not finite.
    static void Normalize(const double v[3], double n[3])
    {
      const double norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      const bool valid = norm > 0.0 && std::isfinite(norm);
      for (int a = 0; a < 3; ++a)
      {
        n[a] = valid ? v[a] / norm : 0.0;
      }
    }

    // The interval [t0, t1] of the ray o + t v (t >= 0) inside the box of the points; false
    // when it misses.
    bool Clip(const double o[3], const double v[3], double& t0, double& t1) const
    {
      t0 = 0.0;
      t1 = 1e300;
      for (int a = 0; a < 3; ++a)
      {
        if (v[a] == 0.0)
        {
          if (o[a] < 0.0 || o[a] > this->Dims[a] - 1.0)
          {
            return false;
          }
          continue;
        }
        const double ta = -o[a] / v[a], tb = (this->Dims[a] - 1.0 - o[a]) / v[a];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
      }
      return t1 > t0;
    }
  };

  // A table's entries and axes: axis a has Size[a] entries at values Low[a] + i / ToIndex[a].
  // Chords: the axes are (chord centre, chord, deviation) (vtkSecondOrderPreIntegrationTable),
  // else (front, back) (vtkFirstOrderPreIntegrationTable).
  struct TableView
  {
    const float* Entries = nullptr;
    int Dimensions = 2;
    int Size[3] = { 1, 1, 1 };
    double Low[3] = { 0, 0, 0 }, ToIndex[3] = { 0, 0, 0 };
    bool Chords = false;

    // The view of a built table (its scalar range, sizes and, for a
    // vtkSecondOrderPreIntegrationTable, chord and deviation ranges).
    static TableView Of(vtkPreIntegrationTable* table)
    {
      TableView view;
      view.Entries = table->GetTable()->GetPointer(0);
      view.Dimensions = table->GetNumberOfDimensions();
      const double* range = table->GetScalarRange();
      const int n = table->GetTableSize();
      for (int a = 0; a < view.Dimensions; ++a)
      {
        view.Size[a] = n;
        view.Low[a] = range[0];
        view.ToIndex[a] = (n - 1) / (range[1] - range[0]);
      }
      if (auto* chords = vtkSecondOrderPreIntegrationTable::SafeDownCast(table))
      {
        view.Chords = true;
        const double extents[2] = { chords->GetEffectiveChordRange(),
          chords->GetEffectiveDeviationRange() };
        const int sizes[2] = { chords->GetChordSize(), chords->GetDeviationSize() };
        for (int a = 1; a < 3; ++a)
        {
          view.Size[a] = sizes[a - 1];
          view.Low[a] = -extents[a - 1];
          view.ToIndex[a] = sizes[a - 1] > 1 && extents[a - 1] > 0.0
            ? (sizes[a - 1] - 1) / (2.0 * extents[a - 1])
            : 0.0;
        }
      }
      return view;
    }

    // Continuous index along axis a, clamped to the edge entries.
    double Index(int a, double value) const
    {
      return this->Size[a] < 2 ? 0.0
                               : std::min(std::max((value - this->Low[a]) * this->ToIndex[a], 0.0),
                                   static_cast<double>(this->Size[a] - 1));
    }

    // The axis values of a segment (front, back) or of a slab (front, middle, back).
    void SegmentAxes(double sf, double sb, double v[3]) const
    {
      const double c = 0.5 * (sf + sb);
      v[0] = this->Chords ? c : sf;
      v[1] = this->Chords ? sb - sf : sb;
      v[2] = 0.0;
    }
    static void SlabAxes(double sf, double sm, double sb, double v[3])
    {
      const double c = 0.5 * (sf + sb);
      v[0] = c;
      v[1] = sb - sf;
      v[2] = sm - c;
    }

    // The corners of the interpolation cell of axis values v and their weights (2^Dimensions
    // of them; corners of a 1-entry axis repeat with weight 0).
    void Corners(const double v[3], vtkIdType index[8], double weight[8]) const
    {
      int i[3] = { 0, 0, 0 };
      double w[3] = { 0, 0, 0 };
      for (int a = 0; a < this->Dimensions; ++a)
      {
        const double x = this->Index(a, v[a]);
        i[a] = std::min(static_cast<int>(x), std::max(this->Size[a] - 2, 0));
        w[a] = x - i[a];
      }
      const int corners = 1 << this->Dimensions;
      for (int c = 0; c < corners; ++c)
      {
        double product = 1.0;
        vtkIdType offset = 0, stride = 1;
        for (int a = 0; a < this->Dimensions; ++a)
        {
          const int bit = (c >> a) & 1;
          product *= bit ? w[a] : 1.0 - w[a];
          offset += (i[a] + (this->Size[a] > 1 ? bit : 0)) * stride;
          stride *= this->Size[a];
        }
        index[c] = offset;
        weight[c] = product;
      }
    }
  };

  // A partial piece of the GLSL: colour per opacity kept, optical depth scaled.
  static void Scale(double rgba[4], double fraction)
  {
    if (fraction < 1.0)
    {
      const double alpha = 1.0 - std::pow(std::max(1.0 - rgba[3], 0.0), fraction);
      const double scale = rgba[3] > 1e-6 ? alpha / rgba[3] : fraction;
      for (int c = 0; c < 3; ++c)
      {
        rgba[c] *= scale;
      }
      rgba[3] = alpha;
    }
  }

  // Segments and slabs read from a table (every entry computed).
  struct TablePieces
  {
    TableView Table;

    void Read(const double v[3], double fraction, double rgba[4]) const
    {
      vtkIdType index[8];
      double weight[8];
      this->Table.Corners(v, index, weight);
      std::fill(rgba, rgba + 4, 0.0);
      for (int c = 0; c < (1 << this->Table.Dimensions); ++c)
      {
        const float* e = this->Table.Entries + 4 * index[c];
        for (int k = 0; k < 4; ++k)
        {
          rgba[k] += weight[c] * e[k];
        }
      }
      Scale(rgba, fraction);
    }
    void Segment(double sf, double sb, double fraction, double length, double rgba[4]) const
    {
      (void)length;
      double v[3];
      this->Table.SegmentAxes(sf, sb, v);
      this->Read(v, fraction, rgba);
    }
    void Slab(double sf, double sm, double sb, double fraction, double length, double rgba[4]) const
    {
      (void)length;
      double v[3];
      TableView::SlabAxes(sf, sm, sb, v);
      this->Read(v, fraction, rgba);
    }
  };

  // Segments and slabs integrated along their model scalar path.
  struct ExactPieces
  {
    const vtkVolumeTransferFunctionSampler* Sampler = nullptr;
    // Largest scalar change per integration piece, as a fraction of the narrowest feature the
    // piece can meet (features wider than DataRange count as that wide): the reference's rule.
    double Tolerance = 1.0 / 64.0;
    double DataRange = 1.0;

    // The path P(u) = f + b u + a u^2, u in [0, 1], over a world length, in midpoint pieces
    // whose scalar sweep is at most Tolerance times the narrowest feature within their reach
    // (vtkVolumeTransferFunctionSampler::GetLongestSweep, as the reference's pieces).
    // |P'| <= max(|b|, |2a + b|) on [0, 1].
    static double Sweep(double b, double a) { return std::max(std::abs(b), std::abs(2.0 * a + b)); }

    // The values P(u) takes over [0, 1] (its ends and, inside, its vertex), widened by
    // `widen` and against rounding.
    void Range(double f, double b, double a, double widen, double range[2]) const
    {
      range[0] = std::min(f, f + b + a);
      range[1] = std::max(f, f + b + a);
      const double vertex = a != 0.0 ? -b / (2.0 * a) : -1.0;
      if (vertex > 0.0 && vertex < 1.0)
      {
        range[0] = std::min(range[0], f + vertex * (b + vertex * a));
        range[1] = std::max(range[1], f + vertex * (b + vertex * a));
      }
      const double margin = 1e-9 * (std::abs(f) + std::abs(b) + std::abs(a) + this->DataRange);
      range[0] -= widen + margin;
      range[1] += widen + margin;
    }

    // A slab's path (Eq. 2: P(u) = A u^2 + B u + sf) as (b, a) = (B, A).
    static void SlabPath(double sf, double sm, double sb, double& b, double& a)
    {
      b = -3.0 * sf + 4.0 * sm - sb;
      a = 2.0 * sf - 4.0 * sm + 2.0 * sb;
    }

    // The scalars Integrate() reads the transfer functions at for this path: its values
    // widened by its sweep (GetLongestSweep's queries reach that far from a value).
    void Reach(double f, double b, double a, double range[2]) const
    {
      this->Range(f, b, a, Sweep(b, a), range);
    }

    void Integrate(double f, double b, double a, double length, double rgba[4]) const
    {
      const double sweep = Sweep(b, a);
      const double shortest = 1e-5; // at most 1e5 pieces
      double transmittance = 1.0;
      std::fill(rgba, rgba + 4, 0.0);
      // A path whose values meet no opacity gives exactly what its pieces would: nothing.
      double values[2];
      this->Range(f, b, a, 0.0, values);
      if (this->Sampler->GetMaximumOpacity(values[0], values[1]) <= 0.0)
      {
        return;
      }
      for (double u = 0.0; u < 1.0;)
      {
        double du = 1.0 - u;
        if (sweep > 0.0)
        {
          const double reach = this->Sampler->GetLongestSweep(
            f + u * (b + u * a), this->Tolerance, this->DataRange, sweep * du);
          du = std::min(du, std::max(reach / sweep, shortest));
        }
        if (1.0 - u - du < shortest)
        {
          du = 1.0 - u;
        }
        const double middle = u + 0.5 * du;
        u += du;
        double sample[4];
        this->Sampler->Evaluate(f + middle * (b + middle * a), sample);
        const double alpha = -std::expm1(-sample[3] * length * du);
        const double weight = transmittance * alpha;
        for (int c = 0; c < 3; ++c)
        {
          rgba[c] += weight * sample[c];
        }
        transmittance *= 1.0 - alpha;
      }
      rgba[3] = 1.0 - transmittance;
    }
    void Segment(double sf, double sb, double fraction, double length, double rgba[4]) const
    {
      this->Integrate(sf, sb - sf, 0.0, fraction * length, rgba);
    }
    void Slab(double sf, double sm, double sb, double fraction, double length, double rgba[4]) const
    {
      double b, a;
      SlabPath(sf, sm, sb, b, a);
      this->Integrate(sf, b, a, fraction * length, rgba);
    }
  };

  // Shaded first-order segments read from the moment layers of a first-order
  // vtkSecondOrderPreIntegrationTable (Moments > 0) and lit by the model's ShadeSegment(), as
  // hovrPreIntegrationShading.glsl does: each layer is read with the bilinear lookup of
  // TablePieces (layers missing from the table read as zero), the opacity is J'_0 + J'_1 and
  // a partial segment is scaled as an unshaded one.
  struct ShadedTablePieces
  {
    TableView Table;           // the first layer's view
    int Layers = 0;            // layers the table stores
    vtkIdType LayerStride = 0; // entries per layer
    const vtkVolumeShadingModel* Model = nullptr;
    double View[3] = { 0, 0, 1 }; // unit, towards the eye: set per ray

    void ShadedSegment(double sf,
      double sb,
      const double nf[3],
      const double nb[3],
      double fraction,
      double length,
      double rgba[4]) const
    {
      (void)length;
      double v[3];
      this->Table.SegmentAxes(sf, sb, v);
      vtkIdType index[8];
      double weight[8];
      this->Table.Corners(v, index, weight);
      double moments[4][4] = {};
      for (int l = 0; l < std::min(this->Layers, 4); ++l)
      {
        for (int c = 0; c < (1 << this->Table.Dimensions); ++c)
        {
          const float* e = this->Table.Entries + 4 * (index[c] + l * this->LayerStride);
          for (int k = 0; k < 4; ++k)
          {
            moments[l][k] += weight[c] * e[k];
          }
        }
      }
      this->Model->ShadeSegment(moments, nf, nb, this->View, rgba);
      rgba[3] = moments[0][3] + moments[1][3];
      Scale(rgba, fraction);
    }

    // A second-order slab from a table with SlabMoments (Layers = 2 SlabMoments): each half's
    // moments read with the trilinear lookup of TablePieces and shaded as a segment between
    // its end normals, (nf, nm) and (nm, nb); the two summed, as hovrPreIntegration2.glsl
    // does. Opacity: J'_0 + J'_1 of both halves.
    void ShadedSlab(double sf,
      double sm,
      double sb,
      const double nf[3],
      const double nm[3],
      const double nb[3],
      double fraction,
      double length,
      double rgba[4]) const
    {
      (void)length;
      double v[3];
      TableView::SlabAxes(sf, sm, sb, v);
      vtkIdType index[8];
      double weight[8];
      this->Table.Corners(v, index, weight);
      const int half = this->Layers / 2;
      double alpha = 0.0;
      std::fill(rgba, rgba + 3, 0.0);
      for (int p = 0; p < 2; ++p)
      {
        double moments[4][4] = {};
        for (int l = 0; l < std::min(half, 4); ++l)
        {
          for (int c = 0; c < (1 << this->Table.Dimensions); ++c)
          {
            const float* e =
              this->Table.Entries + 4 * (index[c] + (p * half + l) * this->LayerStride);
            for (int k = 0; k < 4; ++k)
            {
              moments[l][k] += weight[c] * e[k];
            }
          }
        }
        double rgb[3];
        this->Model->ShadeSegment(moments, p == 0 ? nf : nm, p == 0 ? nm : nb, this->View, rgb);
        for (int c = 0; c < 3; ++c)
        {
          rgba[c] += rgb[c];
        }
        alpha += moments[0][3] + moments[1][3];
      }
      rgba[3] = alpha;
      Scale(rgba, fraction);
    }
  };

  // Shaded first-order segments integrated along the segment model (the segment-model reference):
  // the scalar linear from front to back, the normal nlerp(nf, nb, u) exactly normalised (zero
  // where it vanishes), lit point by point by the model's ShadePoint(); Substeps midpoint steps
  // per segment, more where the transfer function needs them (ExactPieces' rule), each
  // composited with the exact exponential of its extinction. A segment whose scalar meets no
  // opacity adds nothing and is skipped.
  struct ShadedExactPieces
  {
    const vtkVolumeTransferFunctionSampler* Sampler = nullptr;
    const vtkVolumeShadingModel* Model = nullptr;
    int Substeps = 256;
    double Tolerance = 1.0 / 64.0;
    double DataRange = 1.0;
    double View[3] = { 0, 0, 1 }; // unit, towards the eye: set per ray

    void ShadedSegment(double sf,
      double sb,
      const double nf[3],
      const double nb[3],
      double fraction,
      double length,
      double rgba[4]) const
    {
      std::fill(rgba, rgba + 4, 0.0);
      const double lo = std::min(sf, sb), hi = std::max(sf, sb);
      if (!(this->Sampler->GetMaximumOpacity(lo, hi) > 0.0))
      {
        return;
      }
      const double feature = std::min(this->Sampler->GetSmallestFeature(lo, hi), this->DataRange);
      const double step = feature > 0.0 && feature < 1e300 ? this->Tolerance * feature : 1e300;
      const int n = static_cast<int>(std::min(
        std::max(std::ceil((hi - lo) / step), static_cast<double>(std::max(this->Substeps, 1))),
        1e6));
      const double h = fraction * length / n;
      double transmittance = 1.0;
      for (int k = 0; k < n; ++k)
      {
        const double u = (k + 0.5) / n;
        double sample[4];
        this->Sampler->Evaluate(sf + u * (sb - sf), sample);
        if (!(sample[3] > 0.0))
        {
          continue;
        }
        this->CompositeStep(sample, nf, nb, u, h, transmittance, rgba);
      }
      rgba[3] = 1.0 - transmittance;
    }

    // A second-order slab along its model: the scalar on the quadratic through (sf, sm, sb)
    // (Eq. 2), the normal nlerp(nf, nm, 2u) over the front half and nlerp(nm, nb, 2u - 1)
    // over the back half, exactly normalised; steps as ShadedSegment's, an even number.
    void ShadedSlab(double sf,
      double sm,
      double sb,
      const double nf[3],
      const double nm[3],
      const double nb[3],
      double fraction,
      double length,
      double rgba[4]) const
    {
      std::fill(rgba, rgba + 4, 0.0);
      const double b = -3.0 * sf + 4.0 * sm - sb, a = 2.0 * sf - 4.0 * sm + 2.0 * sb;
      double lo = std::min(sf, sb), hi = std::max(sf, sb);
      const double vertex = a != 0.0 ? -b / (2.0 * a) : -1.0;
      if (vertex > 0.0 && vertex < 1.0)
      {
        lo = std::min(lo, sf + vertex * (b + a * vertex));
        hi = std::max(hi, sf + vertex * (b + a * vertex));
      }
      if (!(this->Sampler->GetMaximumOpacity(lo, hi) > 0.0))
      {
        return;
      }
      const double sweep = std::max(std::abs(b), std::abs(2.0 * a + b));
      const double feature = std::min(this->Sampler->GetSmallestFeature(lo, hi), this->DataRange);
      const double step = feature > 0.0 && feature < 1e300 ? this->Tolerance * feature : 1e300;
      int n = static_cast<int>(std::min(
        std::max(std::ceil(sweep / step), static_cast<double>(std::max(this->Substeps, 1))), 1e6));
      n += n % 2;
      const double h = fraction * length / n;
      double transmittance = 1.0;
      for (int k = 0; k < n; ++k)
      {
        const double u = (k + 0.5) / n;
        double sample[4];
        this->Sampler->Evaluate(sf + u * (b + u * a), sample);
        if (!(sample[3] > 0.0))
        {
          continue;
        }
        const bool front = 2 * k < n;
        const double* n0 = front ? nf : nm;
        const double* n1 = front ? nm : nb;
        this->CompositeStep(
          sample, n0, n1, front ? 2.0 * u : 2.0 * u - 1.0, h, transmittance, rgba);
      }
      rgba[3] = 1.0 - transmittance;
    }

    // One midpoint step of length h with the transfer function's sample (c, tau), lit with
    // nlerp(n0, n1, w) exactly normalised, composited front to back into rgb.
    void CompositeStep(const double sample[4],
      const double n0[3],
      const double n1[3],
      double w,
      double h,
      double& transmittance,
      double rgba[4]) const
    {
      const double mix[3] = {
        (1.0 - w) * n0[0] + w * n1[0], (1.0 - w) * n0[1] + w * n1[1], (1.0 - w) * n0[2] + w * n1[2]
      };
      double normal[3], colour[3] = { sample[0], sample[1], sample[2] }, shaded[3];
      Grid::Normalize(mix, normal);
      this->Model->ShadePoint(normal, this->View, colour, shaded);
      const double alpha = -std::expm1(-sample[3] * h);
      const double weight = transmittance * alpha;
      for (int c = 0; c < 3; ++c)
      {
        rgba[c] += weight * shaded[c];
      }
      transmittance *= 1.0 - alpha;
    }
  };

  // Whether a Pieces policy shades (has ShadedSegment): Cast then computes the normals at the
  // samples and composites first order only.
  template <class Pieces, class = void>
  struct IsShaded : std::false_type
  {
  };
  template <class Pieces>
  struct IsShaded<Pieces, std::void_t<decltype(&Pieces::ShadedSegment)>> : std::true_type
  {
  };

  // Front-to-back compositing; false once the ray is opaque enough to stop. NaN pieces (a
  // NaN sample) add nothing.
  static bool Composite(const double piece[4], double threshold, double rgba[4])
  {
    if (std::isnan(piece[0] + piece[1] + piece[2] + piece[3]))
    {
      return true;
    }
    const double t = 1.0 - rgba[3];
    for (int c = 0; c < 4; ++c)
    {
      rgba[c] += t * piece[c];
    }
    return rgba[3] <= threshold;
  }

  /**
   * The ray o + t v (grid index; t in world units, v the index-space image of a unit world
   * direction) from t0 to t1 inside the box, `order` 1 or 2. Samples lie on the ray's own grid,
   * t = k step for integers k, whatever part of the ray is integrated, so that pieces of a ray
   * (bricks of a volume, pieces on MPI ranks) sample where the whole ray does. First order
   * integrates the segments between the entry t0, the samples inside and the exit t1. Second
   * order integrates slabs between even samples (k even) where a whole slab fits between t0
   * and t1, through its front, middle (the odd sample) and back; the pieces before the first
   * even sample and after the last whole slab end on every sample, so that none is longer than
   * a step, and are integrated as slabs through their front, midpoint and back, scaled to their
   * length. Shaded pieces (IsShaded) get the grid's
   * normals at both ends of each segment (first order) or at the front, middle and back of
   * each slab (second order).
   */
  template <class Pieces>
  static void Cast(const Grid& grid,
    const Pieces& pieces,
    int order,
    double step,
    double threshold,
    const double o[3],
    const double v[3],
    double t0,
    double t1,
    double rgba[4])
  {
    std::fill(rgba, rgba + 4, 0.0);
    auto at = [&](double t)
    {
      const double p[3] = { o[0] + t * v[0], o[1] + t * v[1], o[2] + t * v[2] };
      return grid.Sample(p);
    };
    constexpr bool shaded = IsShaded<Pieces>::value;
    auto normalAt = [&](double t, double n[3])
    {
      if (shaded)
      {
        const double p[3] = { o[0] + t * v[0], o[1] + t * v[1], o[2] + t * v[2] };
        grid.Normal(p, n);
      }
    };
    if (!(t1 > t0))
    {
      return;
    }
    // The pieces end on the samples k step after the entry (second order: on the even ones
    // only where a whole slab fits), then at the exit.
    const double h = step;
    const double span = order == 1 ? h : 2.0 * h;
    double k = std::floor(t0 / h) + 1.0;
    const double firstEven = std::fmod(k, 2.0) == 0.0 ? k : k + 1.0;
    double piece[4];
    double tFront = t0;
    double sFront = at(t0);
    double nFront[3] = { 0, 0, 0 }, nMiddle[3] = { 0, 0, 0 }, nBack[3] = { 0, 0, 0 };
    normalAt(t0, nFront);
    for (;;)
    {
      const bool last = k * h >= t1;
      const double tBack = last ? t1 : k * h;
      const double fraction = (tBack - tFront) / span;
      if (fraction > 0.0)
      {
        const double sBack = at(tBack);
        normalAt(tBack, nBack);
        if (order == 1)
        {
          // A NaN sample makes its segments transparent (the GLSL skips them).
          if (std::isnan(sFront + sBack))
          {
            std::fill(piece, piece + 4, 0.0);
          }
          else if constexpr (shaded)
          {
            pieces.ShadedSegment(sFront, sBack, nFront, nBack, fraction, h, piece);
          }
          else
          {
            pieces.Segment(sFront, sBack, fraction, h, piece);
          }
        }
        else
        {
          const double tMiddle = 0.5 * (tFront + tBack);
          const double sMiddle = at(tMiddle);
          normalAt(tMiddle, nMiddle);
          if (std::isnan(sFront + sMiddle + sBack))
          {
            std::fill(piece, piece + 4, 0.0);
          }
          else if constexpr (shaded)
          {
            pieces.ShadedSlab(
              sFront, sMiddle, sBack, nFront, nMiddle, nBack, fraction, span, piece);
          }
          else
          {
            pieces.Slab(sFront, sMiddle, sBack, fraction, span, piece);
          }
        }
        if (!Composite(piece, threshold, rgba))
        {
          return;
        }
        tFront = tBack;
        sFront = sBack;
        std::copy(nBack, nBack + 3, nFront);
      }
      if (last)
      {
        return;
      }
      // From an even sample a whole slab, when it fits before the exit.
      k +=
        order == 2 && k >= firstEven && std::fmod(k, 2.0) == 0.0 && (k + 2.0) * h <= t1 ? 2.0 : 1.0;
    }
  }
};

#endif
