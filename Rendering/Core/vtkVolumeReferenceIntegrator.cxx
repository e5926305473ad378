// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkVolumeReferenceIntegrator.h"

#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkErrorForwarder.h"
#include "vtkFloatArray.h"
#include "vtkGridRayTraversal.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLowPriorityThreads.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTrilinearRayProfile.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeShadingModel.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <new>
#include <numeric>
#include <random>
#include <vector>

vtkStandardNewMacro(vtkVolumeReferenceIntegrator);

namespace
{
// Everything a ray needs, read-only and shared by the threads.
struct VolumeGrid
{
  vtkVolumeScalarView Values; // x fastest
  int Dims[3];
  double PhysicalToIndex[16]; // world point -> 0-based continuous grid index
};

// Where the ray o + t v enters a cell at t0, in the cell's local coordinates.
void CellEntry(const double o[3], const double v[3], double t0, const int cell[3], double u0[3])
{
  for (int a = 0; a < 3; ++a)
  {
    u0[a] = o[a] + t0 * v[a] - cell[a];
  }
}

class RayCaster
{
public:
  const VolumeGrid& Grid;
  const vtkCameraRayModel* Rays;
  const vtkVolumeTransferFunctionSampler* Sampler;
  double Tolerance; // scalar change per piece, as a fraction of the narrowest local feature
  double DataRange; // features wider than the data's range count as that wide
  double Cutoff;
  int Width;
  float* Output;
  const vtkIdType* Pixels = nullptr; // the pixels to compute, by rank; nullptr: all
  vtkSMPThreadLocal<vtkIdType> Samples;
  // Blend modes other than composite.
  int BlendMode = vtkVolumeReferenceIntegrator::COMPOSITE_BLEND;
  std::vector<double> IsoValues;
  bool Shade = false;
  double Ambient = 0, Diffuse = 1, Specular = 0, SpecularPower = 1;
  double* Extra = nullptr;  // Depth, MaxScalar or MinScalar
  double IsoShift = 0.0;    // isosurface: the isovalue perturbation of DepthSpread
  double* Spread = nullptr; // isosurface: DepthSpread
  // Composite shading: the lighting (nullptr: unshaded) and the pieces per radian of normal
  // turn that its narrowest lobe needs.
  const vtkVolumeShadingModel* Shading = nullptr;
  double PiecesPerRadian = 0.0;
  const double* Normals = nullptr; // 3 per point: the normal array, instead of differences

  RayCaster(const VolumeGrid& grid,
    const vtkCameraRayModel* rays,
    const vtkVolumeTransferFunctionSampler* sampler,
    double tolerance,
    double dataRange,
    double cutoff,
    int width,
    float* output)
    : Grid(grid)
    , Rays(rays)
    , Sampler(sampler)
    , Tolerance(tolerance)
    , DataRange(dataRange)
    , Cutoff(cutoff)
    , Width(width)
    , Output(output)
    , Samples(0)
  {
  }

  void operator()(vtkIdType begin, vtkIdType end)
  {
    vtkIdType& samples = this->Samples.Local();
    for (vtkIdType rank = begin; rank < end; ++rank)
    {
      const vtkIdType p = this->Pixels ? this->Pixels[rank] : rank;
      double rgba[4], extra = std::numeric_limits<double>::quiet_NaN(), spread = 0.0;
      const int i = static_cast<int>(p % this->Width), j = static_cast<int>(p / this->Width);
      switch (this->BlendMode)
      {
        case vtkVolumeReferenceIntegrator::ISOSURFACE_BLEND:
          samples += this->CastIsoSurface(i, j, rgba, extra, spread);
          this->Spread[p] = spread;
          break;
        case vtkVolumeReferenceIntegrator::MAXIMUM_INTENSITY_BLEND:
        case vtkVolumeReferenceIntegrator::MINIMUM_INTENSITY_BLEND:
          samples += this->CastProjection(i, j, rgba, extra);
          break;
        default:
          samples += this->CastRay(i, j, rgba);
      }
      std::copy(rgba, rgba + 4, this->Output + 4 * p);
      if (this->Extra)
      {
        this->Extra[p] = extra;
      }
    }
  }

  // The pixel ray in grid index space (o + t v, t the world distance) and its walk; false
  // when it misses the grid.
  bool StartRay(int i, int j, double o[3], double v[3], vtkGridRayTraversal& walk) const
  {
    double origin[3], direction[3];
    this->Rays->GetPixelRay(i, j, origin, direction);
    const double* m = this->Grid.PhysicalToIndex;
    for (int r = 0; r < 3; ++r)
    {
      o[r] =
        m[4 * r] * origin[0] + m[4 * r + 1] * origin[1] + m[4 * r + 2] * origin[2] + m[4 * r + 3];
      v[r] = m[4 * r] * direction[0] + m[4 * r + 1] * direction[1] + m[4 * r + 2] * direction[2];
    }
    // Parallel rays start on the plane through the camera: volume behind it is not seen,
    // as with VTK's near plane; perspective rays start at the eye.
    return walk.Initialize(this->Grid.Dims, o, v, 0.0, VTK_DOUBLE_MAX);
  }

  // The 8 corner values of a cell, indexed i + 2 j + 4 k; false if any is NaN (the
  // interpolant is NaN in the whole cell: transparent, no surface, no extremum).
  bool GetCorners(const int cell[3], double corner[8]) const
  {
    const int* dims = this->Grid.Dims;
    const vtkIdType sy = dims[0];
    const vtkIdType sz = static_cast<vtkIdType>(dims[0]) * dims[1];
    this->Grid.Values.GetCellCorners(cell[0] + cell[1] * sy + cell[2] * sz, sy, sz, corner);
    return !std::any_of(corner, corner + 8, [](double c) { return std::isnan(c); });
  }

  // The first crossing along the ray o + t v of any isovalue shifted by shift: the hit cell,
  // its entry t0, its corners, the hit's offset best from t0 and its isovalue. Returns false
  // on a miss; cells counts the cells visited.
  struct Hit
  {
    int Cell[3];
    double T0, Best, Value, Corner[8], U0[3];
  };
  bool FindFirstHit(const double o[3],
    const double v[3],
    vtkGridRayTraversal walk,
    double shift,
    Hit& hit,
    vtkIdType& cells) const
  {
    double t1;
    while (walk.Next(hit.Cell, hit.T0, t1))
    {
      ++cells;
      if (!this->GetCorners(hit.Cell, hit.Corner))
      {
        continue;
      }
      // The interpolant stays within its corner range: only values inside can be crossed.
      const auto range = std::minmax_element(hit.Corner, hit.Corner + 8);
      CellEntry(o, v, hit.T0, hit.Cell, hit.U0);
      vtkTrilinearRayProfile profile;
      bool profileSet = false;
      hit.Best = VTK_DOUBLE_MAX;
      for (double isovalue : this->IsoValues)
      {
        const double value = isovalue + shift;
        if (value < *range.first || value > *range.second)
        {
          continue;
        }
        if (!profileSet)
        {
          profile.Set(hit.Corner, hit.U0, v);
          profileSet = true;
        }
        double t;
        if (profile.FindFirstCrossing(value, t1 - hit.T0, t) && t < hit.Best)
        {
          hit.Best = t;
          hit.Value = isovalue;
        }
      }
      if (hit.Best != VTK_DOUBLE_MAX)
      {
        return true;
      }
    }
    return false;
  }

  // The opaque isosurface: first crossing of any isovalue; extra = world depth of the hit,
  // spread = how far it moves when the isovalues move by +-IsoShift (infinite when the ray
  // then misses or starts to hit). Returns the number of cells visited.
  vtkIdType CastIsoSurface(int i, int j, double rgba[4], double& depth, double& spread) const
  {
    rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0.0;
    spread = 0.0;
    double o[3], v[3];
    vtkGridRayTraversal walk;
    if (!this->StartRay(i, j, o, v, walk))
    {
      return 0;
    }
    vtkIdType cells = 0;
    Hit hit;
    const bool found = this->FindFirstHit(o, v, walk, 0.0, hit, cells);
    if (this->IsoShift > 0.0)
    {
      for (const double shift : { -this->IsoShift, this->IsoShift })
      {
        Hit moved;
        vtkIdType ignored = 0;
        if (this->FindFirstHit(o, v, walk, shift, moved, ignored) != found)
        {
          spread = std::numeric_limits<double>::infinity();
        }
        else if (found)
        {
          spread = std::max(spread, std::abs(moved.T0 + moved.Best - hit.T0 - hit.Best));
        }
      }
    }
    if (!found)
    {
      return cells;
    }
    const double* corner = hit.Corner;
    const double* u0 = hit.U0;
    const double best = hit.Best;
    depth = hit.T0 + best;
    double rgbTau[4];
    this->Sampler->Evaluate(hit.Value, rgbTau);
    double light = 1.0, specular = 0.0;
    if (this->Shade)
    {
      // Exact gradient of the trilinear field at the hit, in index space; the world
      // gradient is M^T g for index = M world, and g . v equals the world gradient dotted
      // with the (unit) world ray direction.
      const double u[3] = { u0[0] + best * v[0], u0[1] + best * v[1], u0[2] + best * v[2] };
      double g[3] = { 0, 0, 0 };
      for (int c = 0; c < 8; ++c)
      {
        const double w[3] = {
          (c & 1) ? u[0] : 1 - u[0], (c & 2) ? u[1] : 1 - u[1], (c & 4) ? u[2] : 1 - u[2]
        };
        const double dw[3] = { (c & 1) ? 1.0 : -1.0, (c & 2) ? 1.0 : -1.0, (c & 4) ? 1.0 : -1.0 };
        g[0] += dw[0] * w[1] * w[2] * corner[c];
        g[1] += w[0] * dw[1] * w[2] * corner[c];
        g[2] += w[0] * w[1] * dw[2] * corner[c];
      }
      const double* m = this->Grid.PhysicalToIndex;
      double world[3];
      for (int a = 0; a < 3; ++a)
      {
        world[a] = m[a] * g[0] + m[4 + a] * g[1] + m[8 + a] * g[2];
      }
      const double norm =
        std::sqrt(world[0] * world[0] + world[1] * world[1] + world[2] * world[2]);
      const double nv = norm > 0.0 ? std::abs(g[0] * v[0] + g[1] * v[1] + g[2] * v[2]) / norm : 0.0;
      light = this->Ambient + this->Diffuse * nv;
      specular = nv > 0.0 ? this->Specular * std::pow(nv, this->SpecularPower) : 0.0;
    }
    for (int c = 0; c < 3; ++c)
    {
      rgba[c] = std::min(1.0, rgbTau[c] * light + specular);
    }
    rgba[3] = 1.0;
    return cells;
  }

  // Maximum or minimum intensity projection; extra = the exact extremum (NaN on a miss).
  vtkIdType CastProjection(int i, int j, double rgba[4], double& extremum) const
  {
    rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0.0;
    double o[3], v[3];
    vtkGridRayTraversal walk;
    if (!this->StartRay(i, j, o, v, walk))
    {
      return 0;
    }
    const bool maximum = this->BlendMode == vtkVolumeReferenceIntegrator::MAXIMUM_INTENSITY_BLEND;
    vtkIdType cells = 0;
    int cell[3];
    double t0, t1, corner[8];
    while (walk.Next(cell, t0, t1))
    {
      ++cells;
      if (!this->GetCorners(cell, corner))
      {
        continue;
      }
      // Cells whose corner range cannot beat the current extremum are skipped exactly.
      const auto range = std::minmax_element(corner, corner + 8);
      if (!std::isnan(extremum) && (maximum ? *range.second <= extremum : *range.first >= extremum))
      {
        continue;
      }
      double u0[3];
      CellEntry(o, v, t0, cell, u0);
      vtkTrilinearRayProfile profile;
      profile.Set(corner, u0, v);
      double smin, smax;
      profile.GetRange(t1 - t0, smin, smax);
      const double candidate = maximum ? smax : smin;
      if (std::isnan(extremum) || (maximum ? candidate > extremum : candidate < extremum))
      {
        extremum = candidate;
      }
    }
    if (!std::isnan(extremum))
    {
      double rgbTau[4];
      this->Sampler->Evaluate(extremum, rgbTau);
      rgba[3] = this->Sampler->EvaluateOpacity(extremum);
      for (int c = 0; c < 3; ++c)
      {
        rgba[c] = rgbTau[c] * rgba[3];
      }
    }
    return cells;
  }

  // Integrates one pixel ray; returns the number of integration pieces evaluated.
  vtkIdType CastRay(int i, int j, double rgba[4]) const
  {
    rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0.0;
    double o[3], v[3];
    vtkGridRayTraversal walk;
    if (!this->StartRay(i, j, o, v, walk))
    {
      return 0;
    }
    double view[3] = { 0, 0, 0 };
    if (this->Shading)
    {
      double origin[3];
      this->Rays->GetPixelRay(i, j, origin, view);
      for (double& c : view)
      {
        c = -c;
      }
    }
    return this->Integrate(o, v, walk, rgba, view);
  }

  // The gradient of the field at point p of the grid as VTK's GPU ray caster takes it: the
  // difference of the neighbours one point away along each axis, clamped to the box (a
  // one-sided difference at the faces), not halved; in grid index units.
  void PointGradient(const int p[3], double g[3]) const
  {
    const int* dims = this->Grid.Dims;
    const vtkIdType stride[3] = { 1, dims[0], static_cast<vtkIdType>(dims[0]) * dims[1] };
    const vtkIdType base = p[0] + p[1] * stride[1] + p[2] * stride[2];
    for (int a = 0; a < 3; ++a)
    {
      const vtkIdType up = p[a] + 1 < dims[a] ? stride[a] : 0;
      const vtkIdType down = p[a] > 0 ? stride[a] : 0;
      g[a] = this->Grid.Values[base + up] - this->Grid.Values[base - down];
    }
  }

  // The 8 corner gradients of a cell in world units (the world gradient is M^T g for
  // index = M world), and how far their directions spread, in radians (pi when a corner has
  // no direction).
  double CornerGradients(const int cell[3], double gradients[8][3]) const
  {
    const double* m = this->Grid.PhysicalToIndex;
    double mean[3] = { 0, 0, 0 };
    bool degenerate = false;
    for (int c = 0; c < 8; ++c)
    {
      const int p[3] = { cell[0] + (c & 1), cell[1] + ((c >> 1) & 1), cell[2] + ((c >> 2) & 1) };
      double* w = gradients[c];
      if (this->Normals)
      {
        const int* dims = this->Grid.Dims;
        const double* n =
          this->Normals + 3 * (p[0] + dims[0] * (p[1] + static_cast<vtkIdType>(dims[1]) * p[2]));
        std::copy(n, n + 3, w);
      }
      else
      {
        double g[3];
        this->PointGradient(p, g);
        for (int a = 0; a < 3; ++a)
        {
          w[a] = m[a] * g[0] + m[4 + a] * g[1] + m[8 + a] * g[2];
        }
      }
      const double norm = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
      if (!(norm > 0.0) || !std::isfinite(norm))
      {
        degenerate = true;
        continue;
      }
      for (int a = 0; a < 3; ++a)
      {
        mean[a] += w[a] / norm;
      }
    }
    const double length = std::sqrt(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]);
    if (degenerate || !(length > 0.0))
    {
      return vtkMath::Pi();
    }
    double spread = 0.0;
    for (int c = 0; c < 8; ++c)
    {
      const double* w = gradients[c];
      const double norm = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
      const double cosine = (w[0] * mean[0] + w[1] * mean[1] + w[2] * mean[2]) / (norm * length);
      spread = std::max(spread, std::acos(std::min(std::max(cosine, -1.0), 1.0)));
    }
    return 2.0 * spread;
  }

  // The unit normal at local cell coordinates u: the trilinear interpolation of the corner
  // gradients, normalised (zero where it vanishes or is not finite).
  static void InterpolateNormal(const double gradients[8][3], const double u[3], double n[3])
  {
    n[0] = n[1] = n[2] = 0.0;
    for (int c = 0; c < 8; ++c)
    {
      const double w =
        ((c & 1) ? u[0] : 1 - u[0]) * ((c & 2) ? u[1] : 1 - u[1]) * ((c & 4) ? u[2] : 1 - u[2]);
      for (int a = 0; a < 3; ++a)
      {
        n[a] += w * gradients[c][a];
      }
    }
    const double norm = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int a = 0; a < 3; ++a)
    {
      n[a] = norm > 0.0 && std::isfinite(norm) ? n[a] / norm : 0.0;
    }
  }

  // Integrates the ray o + t v in grid index along its walk; view is the unit world direction
  // towards the eye (used when shading).
  // Calls cell(cell, t0, length, corner) for each cell the walk crosses with a length and
  // finite corners, until it returns false: the cells a ray integrates, and those RayCells
  // counts (kept values stay aligned with the cells only while both walks skip the same).
  template <class Cell>
  void ForEachCell(vtkGridRayTraversal& walk, Cell&& body) const
  {
    int cell[3];
    double t0, t1, corner[8];
    while (walk.Next(cell, t0, t1))
    {
      const double length = t1 - t0;
      if (length > 0.0 && this->GetCorners(cell, corner) && !body(cell, t0, length, corner))
      {
        return;
      }
    }
  }

  // Calls piece(middle, h, scalar) for the pieces of the cell segment [0, length] of profile:
  // as fine as the narrowest transfer-function feature their own values can meet (a piece
  // starting at scalar s and changing by at most slope h per length h meets only the features
  // within that reach of s, so a narrow feature elsewhere in the cell's range needs fine pieces
  // only where the profile comes near it), and at most `longest`. Returns their number.
  template <class Piece>
  int ForEachPiece(const vtkTrilinearRayProfile& profile,
    double length,
    double longest,
    Piece&& piece) const
  {
    const double slope = profile.GetMaximumSlope(length);
    const double shortest = length * 1e-6; // at most a million pieces per cell
    int count = 0;
    for (double t = 0.0; t < length; ++count)
    {
      double h = std::min(longest, length - t);
      if (slope > 0.0)
      {
        const double sweep = this->Sampler->GetLongestSweep(
          profile.Evaluate(t), this->Tolerance, this->DataRange, slope * h);
        h = std::min(h, std::max(sweep / slope, shortest));
      }
      if (length - t - h < shortest)
      {
        h = length - t; // no sliver left over
      }
      const double middle = t + 0.5 * h;
      t += h;
      piece(middle, h, profile.Evaluate(middle));
    }
    return count;
  }

  // Integrates the ray o + t v in grid index along its walk; view is the unit world direction
  // towards the eye (used when shading).
  vtkIdType Integrate(const double o[3],
    const double v[3],
    vtkGridRayTraversal& walk,
    double rgba[4],
    const double view[3] = nullptr) const
  {
    rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0.0;
    double transmittance = 1.0;
    vtkIdType pieces = 0;
    this->ForEachCell(walk,
      [&](const int cell[3], double t0, double length, const double corner[8])
      {
        const auto range = std::minmax_element(corner, corner + 8);
        if (this->Sampler->GetMaximumOpacity(*range.first, *range.second) <= 0.0)
        {
          return true; // The interpolant stays within the corner range: exactly empty.
        }
        double entry[3];
        CellEntry(o, v, t0, cell, entry);
        vtkTrilinearRayProfile profile;
        profile.Set(corner, entry, v);
        double longest = length; // the longest piece
        double gradients[8][3], u0[3];
        CellEntry(o, v, t0, cell, u0);
        const bool shade = this->Shading && view;
        if (shade)
        {
          // Also as fine as the lighting's narrowest lobe where the normals turn: the turn
          // along the piece is at most the corners' spread times the piece's share of a cell.
          const double spread = this->CornerGradients(cell, gradients);
          const double share =
            std::min(length * std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), 1.0);
          longest = length /
            std::max(std::min(std::ceil(spread * share * this->PiecesPerRadian), 1e6), 1.0);
        }
        pieces += this->ForEachPiece(profile,
          length,
          longest,
          [&](double middle, double h, double scalar)
          {
            double sample[4];
            this->Sampler->Evaluate(scalar, sample);
            if (shade && sample[3] > 0.0)
            {
              const double u[3] = {
                u0[0] + middle * v[0], u0[1] + middle * v[1], u0[2] + middle * v[2]
              };
              double normal[3], colour[3] = { sample[0], sample[1], sample[2] };
              InterpolateNormal(gradients, u, normal);
              this->Shading->ShadePoint(normal, view, colour, sample);
            }
            // Exact for a piece of constant colour and extinction.
            const double alpha = -std::expm1(-sample[3] * h);
            const double weight = transmittance * alpha;
            rgba[0] += weight * sample[0];
            rgba[1] += weight * sample[1];
            rgba[2] += weight * sample[2];
            transmittance *= 1.0 - alpha;
          });
        return transmittance >= this->Cutoff;
      });
    rgba[3] = 1.0 - transmittance;
    return pieces;
  }

  // Integrate() cell by cell from the cells' own values, in float, kept in `values` and
  // `kept` (this ray's RayCells): a cell crossed before whose reach (its corner range widened
  // by the profile's sweep over the cell: what its pieces read) misses [changed[0],
  // changed[1]] keeps its values, the others are integrated again (every one without
  // changed). Unshaded.
  void IntegrateCells(const double o[3],
    const double v[3],
    vtkGridRayTraversal& walk,
    double rgba[4],
    int colorNodes,
    const double* changed,
    std::vector<float>& values,
    std::vector<unsigned char>& kept) const
  {
    const size_t stride = 1 + (colorNodes > 0 ? colorNodes : 3);
    std::vector<float> newValues;
    std::vector<unsigned char> newKept;
    newValues.reserve(values.size());
    newKept.reserve(kept.size());
    std::vector<double> weights(colorNodes), nodeColors(3 * colorNodes);
    for (int k = 0; k < colorNodes; ++k)
    {
      std::fill(weights.begin(), weights.end(), 0.0);
      weights[k] = 1.0;
      this->Sampler->CombineColors(weights.data(), &nodeColors[3 * k]);
    }
    rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0.0;
    double transmittance = 1.0;
    // Front to back with a cell's float values (the colour from the nodes' colours weighted),
    // kept or new alike; false once the ray stops.
    auto composite = [&](const float* value)
    {
      double colour[3] = { 0.0, 0.0, 0.0 };
      if (colorNodes > 0)
      {
        for (int k = 0; k < colorNodes; ++k)
        {
          for (int c = 0; c < 3; ++c)
          {
            colour[c] += value[1 + k] * nodeColors[3 * k + c];
          }
        }
      }
      else
      {
        std::copy(value + 1, value + 4, colour);
      }
      for (int c = 0; c < 3; ++c)
      {
        rgba[c] += transmittance * colour[c];
      }
      transmittance *= value[0];
      return transmittance >= this->Cutoff;
    };
    if (changed && !(changed[0] <= changed[1]) && !kept.empty())
    {
      // Nothing a cell reads changed: the kept values alone, where the ray stopped before.
      for (size_t at = 0; at < values.size() && composite(values.data() + at); at += stride)
      {
      }
      rgba[3] = 1.0 - transmittance;
      return;
    }
    size_t crossed = 0, next = 0; // cells crossed, and the next kept values
    this->ForEachCell(walk,
      [&](const int cell[3], double t0, double length, const double corner[8])
      {
        const auto range = std::minmax_element(corner, corner + 8);
        double entry[3];
        CellEntry(o, v, t0, cell, entry);
        vtkTrilinearRayProfile profile;
        profile.Set(corner, entry, v);
        const double sweep = profile.GetMaximumSlope(length) * length;
        const double margin = 1e-9 * (std::abs(*range.first) + std::abs(*range.second) + sweep);
        const bool before = crossed < kept.size();
        const bool had = before && kept[crossed] != 0;
        const bool same = before && changed &&
          (*range.second + sweep + margin < changed[0] ||
            *range.first - sweep - margin > changed[1]);
        ++crossed;
        const size_t at = newValues.size();
        if (same)
        {
          if (had)
          {
            newValues.insert(newValues.end(),
              values.begin() + next * stride,
              values.begin() + (next + 1) * stride);
          }
          newKept.push_back(had ? 1 : 0);
        }
        else if (this->Sampler->GetMaximumOpacity(*range.first, *range.second) <= 0.0)
        {
          newKept.push_back(0); // exactly empty
        }
        else
        {
          // The cell alone, from its entry: transmittance, then colour (or its node weights).
          double cellTransmittance = 1.0, colour[3] = { 0.0, 0.0, 0.0 };
          std::fill(weights.begin(), weights.end(), 0.0);
          this->ForEachPiece(profile,
            length,
            length,
            [&](double, double h, double scalar)
            {
              double sample[4];
              this->Sampler->Evaluate(scalar, sample);
              const double alpha = -std::expm1(-sample[3] * h);
              const double weight = cellTransmittance * alpha;
              if (colorNodes > 0)
              {
                double w[2];
                const int k = this->Sampler->GetColorWeights(scalar, w);
                weights[k] += weight * w[0];
                weights[std::min(k + 1, colorNodes - 1)] += weight * w[1];
              }
              else
              {
                for (int c = 0; c < 3; ++c)
                {
                  colour[c] += weight * sample[c];
                }
              }
              cellTransmittance *= 1.0 - alpha;
            });
          newValues.push_back(static_cast<float>(cellTransmittance));
          if (colorNodes > 0)
          {
            newValues.insert(newValues.end(), weights.begin(), weights.end());
          }
          else
          {
            newValues.insert(newValues.end(), colour, colour + 3);
          }
          newKept.push_back(1);
        }
        next += had ? 1 : 0;
        return newValues.size() == at || composite(newValues.data() + at);
      });
    rgba[3] = 1.0 - transmittance;
    values.swap(newValues);
    kept.swap(newKept);
  }
};
}

//------------------------------------------------------------------------------
vtkVolumeReferenceIntegrator::vtkVolumeReferenceIntegrator() = default;

//------------------------------------------------------------------------------
vtkVolumeReferenceIntegrator::~vtkVolumeReferenceIntegrator()
{
  this->SetShadingModel(nullptr);
  this->SetNormalArrayName(nullptr);
}

//------------------------------------------------------------------------------
vtkCxxSetObjectMacro(vtkVolumeReferenceIntegrator, ShadingModel, vtkVolumeShadingModel);

//------------------------------------------------------------------------------
int vtkVolumeReferenceIntegrator::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  this->NumberOfSamples = 0;
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  const int* size = this->RayModel->GetImageSize();
  const int width = std::max(size[0], 1), height = std::max(size[1], 1);
  const bool iso = this->BlendMode == ISOSURFACE_BLEND;
  const bool projection =
    this->BlendMode == MAXIMUM_INTENSITY_BLEND || this->BlendMode == MINIMUM_INTENSITY_BLEND;
  vtkFloatArray* rgba = this->InitializeOutput(output, true, iso ? 2 : projection ? 1 : 0);
  if (!rgba)
  {
    return 1;
  }
  vtkNew<vtkDoubleArray> extra;
  if (iso || projection)
  {
    extra->SetName(
      iso ? "Depth" : (this->BlendMode == MAXIMUM_INTENSITY_BLEND ? "MaxScalar" : "MinScalar"));
    extra->SetNumberOfTuples(static_cast<vtkIdType>(width) * height);
    extra->FillValue(std::numeric_limits<double>::quiet_NaN());
    output->GetPointData()->AddArray(extra);
  }
  else if (this->BlendMode != COMPOSITE_BLEND)
  {
    vtkErrorMacro("Unsupported blend mode " << this->BlendMode
                                            << ": use composite (0), maximum intensity (1), "
                                               "minimum intensity (2) or isosurface (5).");
    return 1;
  }
  vtkNew<vtkDoubleArray> spread;
  if (iso)
  {
    spread->SetName("DepthSpread");
    spread->SetNumberOfTuples(static_cast<vtkIdType>(width) * height);
    spread->FillValue(0.0f);
    output->GetPointData()->AddArray(spread);
  }

  // Validate; on error the output stays a transparent image of the requested size.
  int dims[3];
  vtkDataArray* scalars = this->PrepareFrame(input, inputVector, dims);
  if (!scalars)
  {
    return 1;
  }

  VolumeGrid grid;
  std::copy(dims, dims + 3, grid.Dims);
  const vtkIdType n = scalars->GetNumberOfTuples();
  if (!grid.Values.SetArray(scalars))
  {
    // Not an exception through the pipeline, which would abort the application.
    vtkErrorMacro("Not enough memory for the double-precision copy of the "
      << dims[0] << " x " << dims[1] << " x " << dims[2] << " volume ("
      << std::ceil(n * sizeof(double) / 1048576.0) << " MiB); the image is empty.");
    return 1;
  }
  // World point -> absolute structured index -> 0-based grid index.
  const int* extent = input->GetExtent();
  std::copy(input->GetPhysicalToIndexMatrix()->GetData(),
    input->GetPhysicalToIndexMatrix()->GetData() + 16,
    grid.PhysicalToIndex);
  for (int r = 0; r < 3; ++r)
  {
    grid.PhysicalToIndex[4 * r + 3] -= extent[2 * r];
  }

  double range[2];
  scalars->GetRange(range, 0);
  const double dataRange = range[1] - range[0]; // finite: checked by PrepareFrame
  std::vector<double> isoValues;
  if (iso)
  {
    vtkContourValues* values = this->VolumeProperty->GetIsoSurfaceValues();
    for (int k = 0; values && k < values->GetNumberOfContours(); ++k)
    {
      if (std::isfinite(values->GetValue(k)))
      {
        isoValues.push_back(values->GetValue(k));
      }
    }
    if (isoValues.empty())
    {
      vtkErrorMacro("Isosurface blending needs at least one finite isosurface value in the "
                    "volume property (GetIsoSurfaceValues()->SetValue(0, v)).");
      return 1;
    }
  }

  RayCaster caster(grid,
    this->RayModel,
    this->Sampler,
    this->ScalarTolerance,
    dataRange,
    this->TransmittanceCutoff,
    width,
    rgba->GetPointer(0));
  caster.BlendMode = this->BlendMode;
  caster.IsoValues = isoValues;
  caster.Extra = (iso || projection) ? extra->GetPointer(0) : nullptr;
  caster.Spread = iso ? spread->GetPointer(0) : nullptr;
  caster.IsoShift = this->IsoPerturbation * dataRange;
  caster.Shade = this->VolumeProperty->GetShade(0) != 0;
  caster.Ambient = this->VolumeProperty->GetAmbient(0);
  caster.Diffuse = this->VolumeProperty->GetDiffuse(0);
  caster.Specular = this->VolumeProperty->GetSpecular(0);
  caster.SpecularPower = this->VolumeProperty->GetSpecularPower(0);
  vtkNew<vtkVolumeShadingModel> headlight;
  std::vector<double> normals;
  if (caster.Shade && this->BlendMode == COMPOSITE_BLEND)
  {
    vtkVolumeShadingModel* shading = this->ShadingModel;
    if (!shading)
    {
      // VTK's default lighting: a white headlight, both sides lit.
      shading = headlight;
      shading->SetFromProperty(this->VolumeProperty);
      const double direction[3] = { 0, 0, 1 }, white[3] = { 1, 1, 1 };
      shading->AddLight(direction, white, white, true);
    }
    caster.Shading = shading;
    if (this->NormalArrayName && *this->NormalArrayName)
    {
      if (!this->ReadNormalArray(input, this->NormalArrayName, n, normals))
      {
        return 1;
      }
      caster.Normals = normals.data();
    }
    // A lobe of power n is about 1/sqrt(n) radians wide; the cone's as wide.
    const double lobes = shading->GetSpecular() != 0.0 && !shading->GetGooch()
      ? std::sqrt(shading->GetSpecularPower())
      : 1.0;
    caster.PiecesPerRadian = lobes / (4.0 * this->ScalarTolerance);
  }

  // A pixel sample: the others hold NaN in every array.
  const vtkIdType pixels = static_cast<vtkIdType>(width) * height;
  std::vector<vtkIdType> sample;
  if (this->PixelFraction < 1.0)
  {
    const vtkIdType count =
      std::max<vtkIdType>(1, static_cast<vtkIdType>(std::llround(this->PixelFraction * pixels)));
    sample.resize(static_cast<size_t>(pixels));
    std::iota(sample.begin(), sample.end(), 0);
    std::mt19937_64 random(static_cast<std::uint64_t>(this->PixelSeed));
    for (vtkIdType k = 0; k < count; ++k)
    {
      std::uniform_int_distribution<vtkIdType> pick(k, pixels - 1);
      std::swap(sample[k], sample[pick(random)]);
    }
    sample.resize(static_cast<size_t>(count));
    std::sort(sample.begin(), sample.end());
    rgba->FillValue(std::numeric_limits<float>::quiet_NaN());
    if (iso || projection)
    {
      extra->FillValue(std::numeric_limits<double>::quiet_NaN());
    }
    if (iso)
    {
      spread->FillValue(std::numeric_limits<double>::quiet_NaN());
    }
    caster.Pixels = sample.data();
  }
  const vtkIdType ranks = caster.Pixels ? static_cast<vtkIdType>(sample.size()) : pixels;
  // In chunks so progress and abort requests are handled on this thread.
  const int chunks = static_cast<int>(std::min<vtkIdType>(ranks, 20));
  for (int c = 0; c < chunks && !this->GetAbortExecute(); ++c)
  {
    vtkSMPTools::For(ranks * c / chunks, ranks * (c + 1) / chunks, caster);
    this->UpdateProgress(static_cast<double>(c + 1) / chunks);
  }
  for (vtkIdType s : caster.Samples)
  {
    this->NumberOfSamples += s;
  }
  if (!this->GetAbortExecute())
  {
    this->WarnIfTransparent(rgba);
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkVolumeReferenceIntegrator::IntegrateRays(const vtkVolumeScalarView& values,
  const int dims[3],
  const vtkVolumeTransferFunctionSampler* sampler,
  double scalarTolerance,
  double dataRange,
  double cutoff,
  vtkIdType count,
  const double* origins,
  const double* directions,
  double* rgba,
  const std::atomic<bool>* abort,
  bool lowPriority,
  RayCells* cells,
  const double* changed)
{
  VolumeGrid grid;
  grid.Values = values;
  std::copy(dims, dims + 3, grid.Dims);
  RayCaster caster(grid, nullptr, sampler, scalarTolerance, dataRange, cutoff, 1, nullptr);
  auto integrate = [&](vtkIdType begin, vtkIdType end)
  {
    for (vtkIdType r = begin; r < end; ++r)
    {
      if (abort && abort->load(std::memory_order_relaxed))
      {
        return;
      }
      vtkGridRayTraversal walk;
      std::fill(rgba + 4 * r, rgba + 4 * r + 4, 0.0);
      if (walk.Initialize(grid.Dims, origins + 3 * r, directions + 3 * r, 0.0, VTK_DOUBLE_MAX))
      {
        if (cells)
        {
          caster.IntegrateCells(origins + 3 * r,
            directions + 3 * r,
            walk,
            rgba + 4 * r,
            cells->ColorNodes,
            changed,
            cells->Values[r],
            cells->Kept[r]);
        }
        else
        {
          caster.Integrate(origins + 3 * r, directions + 3 * r, walk, rgba + 4 * r);
        }
      }
    }
  };
  if (lowPriority)
  {
    vtkLowPriorityThreads::For(count, 16, integrate);
  }
  else
  {
    vtkSMPTools::For(0, count, integrate);
  }
}

//------------------------------------------------------------------------------
void vtkVolumeReferenceIntegrator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "BlendMode: " << this->BlendMode << "\n";
  os << indent << "ScalarTolerance: " << this->ScalarTolerance << "\n";
  os << indent << "TransmittanceCutoff: " << this->TransmittanceCutoff << "\n";
  os << indent << "IsoPerturbation: " << this->IsoPerturbation << "\n";
  os << indent << "PixelFraction: " << this->PixelFraction << "\n";
  os << indent << "PixelSeed: " << this->PixelSeed << "\n";
  os << indent << "NumberOfSamples: " << this->NumberOfSamples << "\n";
  os << indent << "ShadingModel: " << this->ShadingModel << "\n";
  os << indent << "NormalArrayName: " << (this->NormalArrayName ? this->NormalArrayName : "(none)")
     << "\n";
}
