// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkObjectOrderRayCaster.h"

#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkFirstOrderPreIntegrationTable.h"
#include "vtkFloatArray.h"
#include "vtkHierarchicalOcclusionMap.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkMinMaxOctree.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPreIntegrationTable.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bitset>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

// SSE2 (every x86-64 compiler): the sample loop's small vectors; a scalar fallback elsewhere.
#if defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2)
#define HOVR_SSE2 1
#include <emmintrin.h>
#endif

vtkStandardNewMacro(vtkObjectOrderRayCaster);
vtkCxxSetObjectMacro(vtkObjectOrderRayCaster, VolumeMatrix, vtkMatrix4x4);

namespace
{
// The volume is kept in bricks of 8^3 cells that hold their far faces too (9^3 points), so
// that any leaf of the octree (at most 8^3 cells, aligned) lies in one brick with its points
// at fixed strides (section 4.3.4's aim: a cell's corners and its neighbours share cache
// lines), at 1.42 times the memory of a plain float copy.
constexpr int BrickCells = 8;
constexpr int BrickPoints = BrickCells + 1;
constexpr int BrickValues = BrickPoints * BrickPoints * BrickPoints;
constexpr int BrickWords = BrickCells * BrickCells * BrickCells / 64; // a bit per cell
constexpr int MaxLeafLevel = 3; // leaves of at most 8^3 cells: inside one brick
}

namespace
{
// Everything the tiles share, read-only during a frame.
class Frame
{
public:
  // The volume, copied into float bricks (BrickValues each, bricks and their points x
  // fastest); rebuilt when the scalars change.
  vtkDataArray* Scalars = nullptr; // not referenced: only compared
  vtkMTimeType ScalarsTime = 0;
  int Dims[3] = { 0, 0, 0 };
  int Cells[3] = { 0, 0, 0 };
  int BrickCount[3] = { 0, 0, 0 };
  size_t BrickTotal = 0;
  std::vector<float> Bricks;
  // A point's address in Bricks (in the brick where it is not a far face, but for the
  // volume's far faces) is a sum of one term per axis: Address(x, y, z) =
  // AxisAddress[0][x] + AxisAddress[1][y] + AxisAddress[2][z].
  std::vector<size_t> AxisAddress[3];
  // Per brick, its visible cells (a bit per cell, x + 8 y + 64 z) for the classification of
  // version VisibleVersion, and the version they were found for: found when a ray first
  // needs them, once per transfer function, range or data rather than once per frame.
  std::unique_ptr<std::atomic<uint64_t>[]> VisibleBits;
  std::unique_ptr<std::atomic<uint32_t>[]> VisibleVersions;
  uint32_t VisibleVersion = 0;
  // Per brick, its cells a ray took a sample in this frame (same bits), so that each cell
  // counts once whatever the tiles and rays; counted and cleared at the end of the frame.
  std::unique_ptr<std::atomic<uint64_t>[]> SampledBits;

  // The frame: pixel (i, j)'s ray is O + i EX + j EY + t D in grid index, t the world
  // distance from the camera plane; (u, v) = Inverse rows 0-1 applied to (p - O) project a
  // grid point to pixel coordinates.
  double O[3], EX[3], EY[3], D[3], InvD[3];
  bool Still[3];
  double Inverse[3][3];
  int Width = 0, Height = 0;
  double Step = 1.0;
  bool Interleaved = true;
  bool Removal = true;
  float Threshold = 0.999f;
  // Classification: RGBA per entry (alpha for one step), entries at S0 + e / InvStep.
  std::vector<float> Table;
  int Entries = 0;
  double S0 = 0.0, InvStep = 1.0;
  std::vector<int> VisiblePrefix;      // visible bins before bin b
  std::array<double, 5> TableKey = {}; // what the two tables above were built for
  // The octree level whose nodes are rendered as a whole (leaves of 2^LeafLevel cells per
  // edge).
  int LeafLevel = 0;
  // Pre-integrated classification: the first-order table over (front, back) scalar for one
  // step (RGBA premultiplied, front fastest), entries at S0 + e / SegmentInvStep.
  bool Preintegrated = false;
  const float* Segments = nullptr;
  int SegmentEntries = 0;
  double SegmentInvStep = 1.0;
  // Per pixel: where its ray enters and leaves the grid's box (t), empty when it misses.
  std::vector<double> Chords;
  // Shading (0 none, 1 post, 2 pre). Gradients are taken in grid index units (central
  // differences) and turned into data-space normals by ToData (the transposed
  // physical-to-index matrix); Light is the headlight in data space.
  int Shading = 0;
  double ToData[3][3];
  double Light[3];
  float Ambient = 0, Diffuse = 1, Specular = 0, Power = 1;
  // Pre-shading: each point's quantized normal (octahedral bins, and one more index for "no
  // gradient") and, per frame, each bin's (ambient + diffuse |n.l|, specular |n.l|^power).
  std::vector<uint16_t> Directions;
  vtkDataArray* DirectionScalars = nullptr;
  vtkMTimeType DirectionTime = 0;
  double DirectionToData[3][3] = {}; // the ToData the directions were quantized with
  std::vector<float> Reflectance;
  bool FrameReady = false;

  size_t Address(int x, int y, int z) const
  {
    return this->AxisAddress[0][x] + this->AxisAddress[1][y] + this->AxisAddress[2][z];
  }

  void BuildBricks(vtkDataArray* scalars, const int dims[3])
  {
    std::copy(dims, dims + 3, this->Dims);
    for (int a = 0; a < 3; ++a)
    {
      this->Cells[a] = dims[a] - 1;
      this->BrickCount[a] = std::max((this->Cells[a] + BrickCells - 1) / BrickCells, 1);
    }
    const size_t brickStride[3] = { 1,
      static_cast<size_t>(this->BrickCount[0]),
      static_cast<size_t>(this->BrickCount[0]) * this->BrickCount[1] };
    const size_t pointStride[3] = { 1, BrickPoints, BrickPoints * BrickPoints };
    for (int a = 0; a < 3; ++a)
    {
      this->AxisAddress[a].resize(dims[a]);
      for (int v = 0; v < dims[a]; ++v)
      {
        const int brick = std::min(v / BrickCells, this->BrickCount[a] - 1);
        this->AxisAddress[a][v] = brickStride[a] * brick * BrickValues +
          pointStride[a] * static_cast<size_t>(v - brick * BrickCells);
      }
    }
    this->BrickTotal = brickStride[2] * this->BrickCount[2];
    this->Bricks.assign(this->BrickTotal * BrickValues, 0.0f);
    const auto values = vtk::DataArrayValueRange<1>(scalars);
    vtkSMPTools::For(0,
      static_cast<vtkIdType>(this->BrickTotal),
      [&](vtkIdType b0, vtkIdType b1)
      {
        for (vtkIdType b = b0; b < b1; ++b)
        {
          const int origin[3] = { static_cast<int>(b % this->BrickCount[0]) * BrickCells,
            static_cast<int>(b / this->BrickCount[0] % this->BrickCount[1]) * BrickCells,
            static_cast<int>(b / brickStride[2]) * BrickCells };
          float* brick = this->Bricks.data() + b * BrickValues;
          for (int z = origin[2]; z < std::min(origin[2] + BrickPoints, dims[2]); ++z)
          {
            for (int y = origin[1]; y < std::min(origin[1] + BrickPoints, dims[1]); ++y)
            {
              const vtkIdType row =
                static_cast<vtkIdType>(dims[0]) * (y + static_cast<vtkIdType>(dims[1]) * z);
              float* out = brick + BrickPoints * ((y - origin[1]) + BrickPoints * (z - origin[2]));
              for (int x = origin[0]; x < std::min(origin[0] + BrickPoints, dims[0]); ++x)
              {
                out[x - origin[0]] = static_cast<float>(values[row + x]);
              }
            }
          }
        }
      });
    this->VisibleBits.reset(new std::atomic<uint64_t>[this->BrickTotal * BrickWords]);
    this->SampledBits.reset(new std::atomic<uint64_t>[this->BrickTotal * BrickWords]);
    this->VisibleVersions.reset(new std::atomic<uint32_t>[this->BrickTotal]);
    for (size_t w = 0; w < this->BrickTotal * BrickWords; ++w)
    {
      this->SampledBits[w].store(0, std::memory_order_relaxed);
    }
    for (size_t b = 0; b < this->BrickTotal; ++b)
    {
      this->VisibleVersions[b].store(0, std::memory_order_relaxed);
    }
    this->VisibleVersion = 0;
    this->NewClassification();
  }

  // The visible cells of every brick are to be found again (the classification changed).
  void NewClassification()
  {
    if (++this->VisibleVersion == 0) // wrapped: forget every brick's version once
    {
      for (size_t b = 0; b < this->BrickTotal; ++b)
      {
        this->VisibleVersions[b].store(0, std::memory_order_relaxed);
      }
      this->VisibleVersion = 1;
    }
  }

  // The visible cells of brick b (at brick coordinates bc), found the first time a ray needs
  // them for this classification: a cell is visible when its 8 corners are finite and the
  // opacity may be non-zero in their range (Visible), the ranges of all cells found by
  // separable passes (pairs of points along x, then pairs of those along y, then along z).
  // Tiles racing for the same brick find the same bits.
  void BrickVisibility(size_t b, const int bc[3], uint64_t bits[BrickWords]) const
  {
    if (this->VisibleVersions[b].load(std::memory_order_acquire) == this->VisibleVersion)
    {
      for (int w = 0; w < BrickWords; ++w)
      {
        bits[w] = this->VisibleBits[b * BrickWords + w].load(std::memory_order_relaxed);
      }
      return;
    }
    int n[3]; // cells of the brick
    for (int a = 0; a < 3; ++a)
    {
      n[a] = std::min(BrickCells, this->Cells[a] - bc[a] * BrickCells);
    }
    const float* v = this->Bricks.data() + b * BrickValues;
    constexpr int P = BrickPoints, PP = BrickPoints * BrickPoints;
    float low[BrickValues], high[BrickValues]; // at the index of the pair's (first) point
    bool finite = true;
    for (int z = 0; z <= n[2]; ++z)
    {
      for (int y = 0; y <= n[1]; ++y)
      {
        const int r = P * y + PP * z;
        for (int x = 0; x < n[0]; ++x)
        {
          low[r + x] = std::min(v[r + x], v[r + x + 1]);
          high[r + x] = std::max(v[r + x], v[r + x + 1]);
        }
        for (int x = 0; x <= n[0]; ++x)
        {
          finite = finite && std::isfinite(v[r + x]);
        }
      }
    }
    for (int z = 0; z <= n[2]; ++z)
    {
      for (int y = 0; y < n[1]; ++y)
      {
        const int r = P * y + PP * z;
        for (int x = 0; x < n[0]; ++x)
        {
          low[r + x] = std::min(low[r + x], low[r + P + x]);
          high[r + x] = std::max(high[r + x], high[r + P + x]);
        }
      }
    }
    std::fill(bits, bits + BrickWords, uint64_t(0));
    for (int z = 0; z < n[2]; ++z)
    {
      for (int y = 0; y < n[1]; ++y)
      {
        const int r = P * y + PP * z;
        for (int x = 0; x < n[0]; ++x)
        {
          const int cell = x + BrickCells * (y + BrickCells * z);
          bool visible = this->Visible(
            std::min(low[r + x], low[r + PP + x]), std::max(high[r + x], high[r + PP + x]));
          if (visible && !finite)
          {
            // A NaN or infinite corner makes the cell transparent (the interpolant is NaN).
            const float* c = v + r + x;
            for (const int o : { 0, 1, P, P + 1, PP, PP + 1, PP + P, PP + P + 1 })
            {
              visible = visible && std::isfinite(c[o]);
            }
          }
          bits[cell >> 6] |= uint64_t(visible) << (cell & 63);
        }
      }
    }
    for (int w = 0; w < BrickWords; ++w)
    {
      this->VisibleBits[b * BrickWords + w].store(bits[w], std::memory_order_relaxed);
    }
    this->VisibleVersions[b].store(this->VisibleVersion, std::memory_order_release);
  }

  // The 8 corners of cell (i, j, k), indexed x + 2 y + 4 z, and their range; false when one
  // is not finite (NaN or infinite: the cell is transparent).
  bool Corners(int i, int j, int k, float c[8], float& lo, float& hi) const
  {
    bool finite = true;
    lo = std::numeric_limits<float>::infinity();
    hi = -lo;
    for (int n = 0; n < 8; ++n)
    {
      c[n] = this->Bricks[this->Address(i + (n & 1), j + ((n >> 1) & 1), k + (n >> 2))];
      finite = finite && std::isfinite(c[n]);
      lo = std::min(lo, c[n]);
      hi = std::max(hi, c[n]);
    }
    return finite;
  }

  // Central-difference gradient at point (x, y, z) in grid index units (one-sided at the
  // border, 0 where a neighbour is not finite).
  void Gradient(int x, int y, int z, float g[3]) const
  {
    const int p[3] = { x, y, z };
    for (int a = 0; a < 3; ++a)
    {
      int lo[3] = { x, y, z }, hi[3] = { x, y, z };
      lo[a] = std::max(p[a] - 1, 0);
      hi[a] = std::min(p[a] + 1, this->Dims[a] - 1);
      const float d = this->Bricks[this->Address(hi[0], hi[1], hi[2])] -
        this->Bricks[this->Address(lo[0], lo[1], lo[2])];
      g[a] = hi[a] > lo[a] && std::isfinite(d) ? d / static_cast<float>(hi[a] - lo[a]) : 0.0f;
    }
  }

  // The data-space normal (not normalised) of an index-space gradient.
  void DataNormal(const float g[3], double n[3]) const
  {
    for (int r = 0; r < 3; ++r)
    {
      n[r] = this->ToData[r][0] * g[0] + this->ToData[r][1] * g[1] + this->ToData[r][2] * g[2];
    }
  }

  // |n.l| for the headlight of the data-space normal of an index-space gradient; -1 when the
  // gradient vanishes (no normal: ambient light only).
  double LightCosine(const float g[3]) const
  {
    double n[3];
    this->DataNormal(g, n);
    const double norm = vtkMath::Norm(n);
    return norm > 0.0 ? std::abs(vtkMath::Dot(n, this->Light)) / norm : -1.0;
  }

  // The lighting of a normal at cosine nl (-1: none): the factor on the transfer function's
  // colour (ambient + diffuse |n.l|) and the added highlight (specular |n.l|^power).
  void Lighting(double nl, float& shade, float& highlight) const
  {
    shade = nl < 0.0 ? this->Ambient : this->Ambient + this->Diffuse * static_cast<float>(nl);
    highlight = nl > 0.0 ? this->Specular * static_cast<float>(std::pow(nl, this->Power)) : 0.0f;
  }

  // Whether the opacity can be non-zero somewhere in [lo, hi] (conservative: whole bins).
  bool Visible(double lo, double hi) const
  {
    if (!(lo <= hi) || this->Entries < 2)
    {
      return false;
    }
    // Clamped to [0, last] before the conversion, which then truncates like floor.
    const double last = this->Entries - 2;
    const int b0 = static_cast<int>(std::min(std::max((lo - this->S0) * this->InvStep, 0.0), last));
    const int b1 = static_cast<int>(std::min(std::max((hi - this->S0) * this->InvStep, 0.0), last));
    return this->VisiblePrefix[b1 + 1] - this->VisiblePrefix[b0] > 0;
  }

  // Pixel rectangle of the box [lo, hi] (grid index) clipped to [x0, x1] x [y0, y1]; false
  // when empty. Pixel i's ray passes through u = i, so the pixels whose rays can meet the box
  // lie within its projection's extent.
  bool Rectangle(const double lo[3], const double hi[3], const int clip[4], int rect[4]) const
  {
    double c[3], h[3];
    for (int a = 0; a < 3; ++a)
    {
      c[a] = 0.5 * (lo[a] + hi[a]) - this->O[a];
      h[a] = 0.5 * (hi[a] - lo[a]);
    }
    const double u = vtkMath::Dot(this->Inverse[0], c), v = vtkMath::Dot(this->Inverse[1], c);
    const double hu = std::abs(this->Inverse[0][0]) * h[0] + std::abs(this->Inverse[0][1]) * h[1] +
      std::abs(this->Inverse[0][2]) * h[2] + 1e-6;
    const double hv = std::abs(this->Inverse[1][0]) * h[0] + std::abs(this->Inverse[1][1]) * h[1] +
      std::abs(this->Inverse[1][2]) * h[2] + 1e-6;
    // Clipped in double to [lo - 1, hi + 1] before the conversion, which would overflow under
    // extreme zoom; the bounds are integers, so rounding after clipping is the same.
    auto ceilIn = [](double x, int lo, int hi)
    {
      x = std::min(std::max(x, lo - 1.0), hi + 1.0);
      const int n = static_cast<int>(x); // truncates towards 0
      return n + (n < x ? 1 : 0);
    };
    auto floorIn = [](double x, int lo, int hi)
    {
      x = std::min(std::max(x, lo - 1.0), hi + 1.0);
      const int n = static_cast<int>(x);
      return n - (n > x ? 1 : 0);
    };
    rect[0] = std::max(ceilIn(u - hu, clip[0], clip[1]), clip[0]);
    rect[1] = std::min(floorIn(u + hu, clip[0], clip[1]), clip[1]);
    rect[2] = std::max(ceilIn(v - hv, clip[2], clip[3]), clip[2]);
    rect[3] = std::min(floorIn(v + hv, clip[2], clip[3]), clip[3]);
    return rect[0] <= rect[1] && rect[2] <= rect[3];
  }
};

// The index of the lowest and of the highest set bit of a non-zero word.
int LowestBit(uint64_t word)
{
#if defined(__GNUC__) || defined(__clang__)
  return __builtin_ctzll(word);
#else
  int k = 0;
  while (!((word >> k) & 1))
  {
    ++k;
  }
  return k;
#endif
}

int HighestBit(uint64_t word)
{
#if defined(__GNUC__) || defined(__clang__)
  return 63 - __builtin_clzll(word);
#else
  int k = 63;
  while (!((word >> k) & 1))
  {
    --k;
  }
  return k;
#endif
}

// Inlined whatever the compiler's size heuristics say: the sample loop is one large function
// in which GCC otherwise calls the trilinear interpolation out of line at every sample.
#if defined(__GNUC__) || defined(__clang__)
#define HOVR_ALWAYS_INLINE inline __attribute__((always_inline))
#elif defined(_MSC_VER)
#define HOVR_ALWAYS_INLINE __forceinline
#else
#define HOVR_ALWAYS_INLINE inline
#endif

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

// Octahedral bins of unit directions for pre-shading: Bins x Bins of them (8100, about the
// paper's 8192).
constexpr int Bins = 90;

// The octahedral map of a unit direction to [-1, 1]^2 and back.
void FoldOctahedron(double p[2])
{
  const double q[2] = { (1.0 - std::abs(p[1])) * (p[0] >= 0.0 ? 1.0 : -1.0),
    (1.0 - std::abs(p[0])) * (p[1] >= 0.0 ? 1.0 : -1.0) };
  p[0] = q[0];
  p[1] = q[1];
}

int DirectionBin(const double n[3])
{
  const double l1 = std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]);
  double p[2] = { n[0] / l1, n[1] / l1 };
  if (n[2] < 0.0)
  {
    FoldOctahedron(p);
  }
  const int i = std::min(std::max(static_cast<int>((p[0] + 1.0) * 0.5 * Bins), 0), Bins - 1);
  const int j = std::min(std::max(static_cast<int>((p[1] + 1.0) * 0.5 * Bins), 0), Bins - 1);
  return i + Bins * j;
}

void BinDirection(int bin, double n[3])
{
  double p[2] = { ((bin % Bins) + 0.5) / Bins * 2.0 - 1.0,
    ((bin / Bins) + 0.5) / Bins * 2.0 - 1.0 };
  n[2] = 1.0 - std::abs(p[0]) - std::abs(p[1]);
  if (n[2] < 0.0)
  {
    FoldOctahedron(p);
  }
  n[0] = p[0];
  n[1] = p[1];
  vtkMath::Normalize(n);
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

// One ray segment through a leaf: the cell and cell-local coordinates of its point at
// entry + dt direction. With SSE2 the three axes take one vector operation each (measured:
// 6% less time per frame on the semi-transparent cases than the scalar loop); both paths
// give the same cells and coordinates.
class SegmentCells
{
public:
  SegmentCells(const LeafCells& cells, const float entry[3])
#ifdef HOVR_SSE2
    : Entry(_mm_setr_ps(entry[0], entry[1], entry[2], 0.0f))
    , Direction(_mm_setr_ps(cells.Direction[0], cells.Direction[1], cells.Direction[2], 0.0f))
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
#ifndef HOVR_SSE2
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
  const __m128 Entry, Direction, Offset, Sign, Top;
  const __m128i Down, Base;
#else
  const LeafCells& Cells;
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

// A pixel's ray between leaves: its chord through the volume (Frame::Chords), its
// premultiplied RGBA so far and, for pre-integration, its last sample (scalar, t: NaN when
// none) and the trailing half step that sample may still owe (its scalar, NaN when nothing
// is owed, and its shading: factor, highlight).
struct PixelState
{
  double Chord[2];
  float RGBA[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
  double PreviousT = std::numeric_limits<double>::quiet_NaN();
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
  // fall in the same few cache sets (measured at 512x512: 11-12% less time per frame).
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
    const double full = a0[3] + f * (a0[7] - a0[3]);
    // alpha = 1 - (1 - full)^(length / step); the two lengths most pieces have (a whole step
    // and half of one) without the logarithm and exponential (to 1e-12 of the exponent).
    const double ratio = length / step;
    double a;
    if (std::abs(ratio - 1.0) <= 1e-12)
    {
      a = full;
    }
    else if (std::abs(ratio - 0.5) <= 1e-12)
    {
      a = full / (1.0 + std::sqrt(1.0 - full)); // 1 - sqrt(1 - full), without cancellation
    }
    else
    {
      a = -std::expm1(std::log1p(-full) * ratio);
    }
    const float alpha = static_cast<float>(a);
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
      for (int py = clip[2]; py <= clip[3]; ++py)
      {
        const double* chords =
          this->I.Chords.data() + 2 * (clip[0] + static_cast<size_t>(this->I.Width) * py);
        for (int lx = 0; lx < this->TileWidth; ++lx)
        {
          PixelState& state =
            this->Pixels[lx + static_cast<size_t>(this->TileWidth) * (py - clip[2])];
          state.Chord[0] = chords[2 * lx];
          state.Chord[1] = chords[2 * lx + 1];
        }
      }
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
    // since the positions outside it fall in transparent cells (measured on headsq-semi:
    // 28% fewer positions, 22% fewer pixels tested, 7% less time per frame).
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
    const LeafCells cells(this->Direction, size);
    const double step = I.Step;
    const double perStep = 1.0 / step; // a product per pixel instead of a division
    const double interleave = I.Interleaved ? 0.5 * step : 0.0; // the odd pixels' phase
    vtkIdType samples = 0; // added to this->Samples at the end (not per sample:
                           // the member may alias the image for the compiler)
    for (int py = rect[2]; py <= rect[3]; ++py)
    {
      const double row[3] = { I.O[0] + py * I.EY[0], I.O[1] + py * I.EY[1], I.O[2] + py * I.EY[2] };
      for (int px = rect[0]; px <= rect[1]; ++px)
      {
        const int lx = px - this->Clip[0], ly = py - this->Clip[2];
        if (this->Occlusion.IsPixelOpaque(lx, ly))
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
        double n = static_cast<double>(static_cast<long long>((tin - phase) * perStep));
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
        PixelState& state = this->Pixels[lx + static_cast<size_t>(this->TileWidth) * ly];
        if (this->Segment<Preintegrated, Shading>(
              state, phase, n, tin, tout, entry, cells, lo, leaf, samples))
        {
          this->Occlusion.SetPixelOpaque(lx, ly);
        }
      }
    }
    this->Samples += samples;
    leaf.Flush(I);
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

  // The part [tin, tout) of a pixel's ray (its state) in the leaf at lo, from its sample
  // phase + n step on; entry: the ray at tin, leaf-local (its direction is Direction). Each
  // sample position finds its cell from its leaf-local coordinates (cells), in the leaf's
  // small float coordinates, and is taken when that cell is visible. (Measured against a walk
  // cell by cell: no branch per cell crossed, whose outcome the branch predictor misses often,
  // and fewer instructions on small cells.)
  // The ray's state is held in locals meanwhile. Specialized for the classification and the
  // shading, so the loop holds only the code the scene needs. True when the pixel became
  // opaque.
  template <bool Preintegrated, int Shading>
  bool Segment(PixelState& state,
    double phase,
    double n,
    double tin,
    double tout,
    const float entry[3],
    const LeafCells& cells,
    const int lo[3],
    LeafView& leaf,
    vtkIdType& samples)
  {
    const auto& I = this->I;
    const double step = I.Step;
    const double te = state.Chord[0], tx = state.Chord[1];
    const float threshold = I.Threshold;
    float acc[4] = { state.RGBA[0], state.RGBA[1], state.RGBA[2], state.RGBA[3] };
    // Pre-integration: the previous sample (scalar, t: NaN when none) and the trailing half
    // step it may still owe (its scalar, NaN when nothing is owed, and its shading).
    float previousScalar = 0.0f, pendingScalar = 0.0f, pendingShade[2] = { 0.0f, 0.0f };
    double previousT = 0.0;
    if (Preintegrated)
    {
      previousScalar = state.PreviousScalar;
      previousT = state.PreviousT;
      pendingScalar = state.PendingScalar;
      pendingShade[0] = state.PendingShade[0];
      pendingShade[1] = state.PendingShade[1];
    }
    // The previous sample's place in the segment table, kept rather than found again for
    // each segment (measured: 4-8% less time per frame on the bench, same images).
    TablePlace previousPlace = Preintegrated ? this->SegmentPlace(previousScalar) : TablePlace();
    double t = phase + n * step;
    float corners[8], gradients[3][8], lit[2][8];
    int loaded = -1; // the bit of the cell whose shading data are loaded
    bool opaque = false;
    const SegmentCells locator(cells, entry);
    for (; t < tout && !opaque; n += 1.0, t = phase + n * step)
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
        I.Lighting(I.LightCosine(g), shade, highlight);
      }
      else if (Shading == 2)
      {
        shade = Trilinear(lit[0], u);
        highlight = Trilinear(lit[1], u);
      }
      alignas(16) float piece[4];
      const bool last = t + step >= tx;
      if (Preintegrated)
      {
        // Pre-integrated segments between consecutive samples (Engel et al.'s table, the
        // project's vtkFirstOrderPreIntegrationTable); point-sampled pieces from the
        // chord's entry (or after a gap of transparent cells) to the first sample and
        // from the last one to the exit.
        const bool joined = previousT == previousT && t - previousT < 1.5 * step;
        const TablePlace place = this->SegmentPlace(s);
        if (!joined && pendingScalar == pendingScalar)
        {
          // After a gap of transparent cells: the previous sample's trailing half step.
          this->ScalarPiece(pendingScalar, 0.5 * step, piece);
          opaque = Composite<Shading>(acc, piece, pendingShade[0], pendingShade[1], threshold);
        }
        if (!opaque)
        {
          if (joined)
          {
            this->SegmentPiece(previousPlace, place, piece);
          }
          else
          {
            this->ScalarPiece(s, t - (t - step < te ? te : t - 0.5 * step), piece);
          }
          opaque = Composite<Shading>(acc, piece, shade, highlight, threshold);
        }
        if (!opaque && last)
        {
          this->ScalarPiece(s, tx - t, piece);
          opaque = Composite<Shading>(acc, piece, shade, highlight, threshold);
        }
        previousScalar = s;
        previousPlace = place;
        previousT = t;
        // Until the next sample joins it by a segment, this one owes its trailing half
        // step (composited after a gap, or at the end of the walk).
        pendingScalar = last ? std::numeric_limits<float>::quiet_NaN() : s;
        pendingShade[0] = shade;
        pendingShade[1] = highlight;
      }
      else
      {
        // Each sample stands for the part of the ray closer to it than to its
        // neighbours, the first one from the box entry on and the last one up to the exit
        // (midpoint rule with the ends included), so no part of the chord is left out or
        // counted twice whatever the phase.
        const bool first = t - step < te; // the first sample of the chord
        if (!first && !last)
        {
          this->StepPiece(s, piece); // a whole step around the sample, as most are
        }
        else
        {
          const double from = first ? te : t - 0.5 * step;
          const double to = last ? tx : t + 0.5 * step;
          this->ScalarPiece(s, to - from, piece);
        }
        opaque = Composite<Shading>(acc, piece, shade, highlight, threshold);
      }
    }
    std::copy(acc, acc + 4, state.RGBA);
    if (Preintegrated)
    {
      state.PreviousScalar = previousScalar;
      state.PreviousT = previousT;
      state.PendingScalar = pendingScalar;
      state.PendingShade[0] = pendingShade[0];
      state.PendingShade[1] = pendingShade[1];
    }
    return opaque;
  }

  // A scalar's place in the pre-integration table: the entry below it and the fraction to
  // the next.
  struct TablePlace
  {
    int Index = 0;
    float Fraction = 0.0f;
  };

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
}

class vtkObjectOrderRayCaster::vtkInternals : public Frame
{
};

//------------------------------------------------------------------------------
vtkObjectOrderRayCaster::vtkObjectOrderRayCaster()
  : SegmentTable(vtkFirstOrderPreIntegrationTable::New())
  , Octree(vtkMinMaxOctree::New())
  , Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkObjectOrderRayCaster::~vtkObjectOrderRayCaster()
{
  this->Octree->Delete();
  this->SegmentTable->Delete();
  this->SetVolumeMatrix(nullptr);
  delete this->Internals;
}

//------------------------------------------------------------------------------
vtkMTimeType vtkObjectOrderRayCaster::GetMTime()
{
  const vtkMTimeType t = this->Superclass::GetMTime();
  return this->VolumeMatrix ? std::max(t, this->VolumeMatrix->GetMTime()) : t;
}

//------------------------------------------------------------------------------
vtkIdType vtkObjectOrderRayCaster::GetMemorySize() const
{
  const vtkInternals& I = *this->Internals;
  return static_cast<vtkIdType>(I.Bricks.size() * sizeof(float) +
           I.Directions.size() * sizeof(uint16_t) +
           I.BrickTotal * (2 * BrickWords * sizeof(uint64_t) + sizeof(uint32_t))) +
    this->Octree->GetMemorySize();
}

//------------------------------------------------------------------------------
int vtkObjectOrderRayCaster::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkInternals& I = *this->Internals;
  I.FrameReady = false;
  this->NumberOfNonTransparentCells = this->NumberOfNodesVisited = this->NumberOfSamples = 0;
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkFloatArray* rgba = this->InitializeOutput(vtkImageData::GetData(outputVector));
  int dims[3];
  vtkDataArray* scalars = this->PrepareFrame(input, inputVector, dims);
  if (!scalars)
  {
    return 1;
  }
  if (!(this->SampleDistance > 0.0) || !std::isfinite(this->SampleDistance))
  {
    vtkErrorMacro(
      "The sample distance must be positive and finite, got " << this->SampleDistance << ".");
    return 1;
  }
  if (!this->GetCamera()->GetParallelProjection())
  {
    vtkErrorMacro("Object-order ray casting needs a parallel projection (every cell projects "
                  "to the same shape); the camera has a perspective one.");
    return 1;
  }

  // The volume: bricks and octree, once per data.
  if (I.Scalars != scalars || I.ScalarsTime < scalars->GetMTime() ||
    !std::equal(dims, dims + 3, I.Dims))
  {
    I.BuildBricks(scalars, dims);
    if (!this->Octree->Build(scalars, dims))
    {
      return 1;
    }
    I.Scalars = scalars;
    I.ScalarsTime = scalars->GetMTime();
  }
  this->UpdateProgress(0.1);

  // Classification table over the data range.
  double range[2];
  scalars->GetFiniteRange(range, 0);
  if (!(range[0] <= range[1]))
  {
    range[0] = 0.0;
    range[1] = 1.0; // only NaN: nothing is drawn, as every cell is transparent
  }
  if (range[1] == range[0])
  {
    range[1] = range[0] + 1.0;
  }
  const int entries = vtkPreIntegrationTable::SuggestTableSize(
    scalars->GetDataType(), range, this->Sampler, 256, 65536);
  I.Entries = this->TableSize = entries;
  I.S0 = range[0];
  I.InvStep = (entries - 1) / (range[1] - range[0]);
  // Rebuilt only when the transfer functions, the range, the size or the step change.
  const std::array<double, 5> tableKey = { static_cast<double>(this->Sampler->GetMTime()),
    range[0],
    range[1],
    static_cast<double>(entries),
    this->SampleDistance };
  if (tableKey != I.TableKey)
  {
    I.TableKey = tableKey;
    I.NewClassification(); // the bricks' visible cells are found again
    std::vector<double> rgbTau(4 * static_cast<size_t>(entries));
    this->Sampler->Sample(range[0], range[1], entries, rgbTau.data());
    I.Table.resize(4 * static_cast<size_t>(entries));
    for (int e = 0; e < entries; ++e)
    {
      for (int ch = 0; ch < 3; ++ch)
      {
        I.Table[4 * e + ch] = static_cast<float>(rgbTau[4 * e + ch]);
      }
      I.Table[4 * e + 3] =
        static_cast<float>(-std::expm1(-rgbTau[4 * e + 3] * this->SampleDistance));
    }
    I.VisiblePrefix.assign(entries, 0);
    for (int b = 0; b + 1 < entries; ++b)
    {
      const double lo = range[0] + b / I.InvStep, hi = range[0] + (b + 1) / I.InvStep;
      const bool visible = this->Sampler->GetMaximumOpacity(lo, hi) > 0.0 ||
        I.Table[4 * b + 3] > 0.0f || I.Table[4 * b + 7] > 0.0f;
      I.VisiblePrefix[b + 1] = I.VisiblePrefix[b] + (visible ? 1 : 0);
    }
  }

  // Pixel rays in grid index (0-based from the extent's first point).
  const int* size = this->GetImageSize();
  I.Width = std::max(size[0], 1);
  I.Height = std::max(size[1], 1);
  // World -> data (the volume's placement) -> grid index.
  vtkNew<vtkMatrix4x4> worldToData; // the inverse of the placement (identity without one)
  if (this->VolumeMatrix)
  {
    if (this->VolumeMatrix->Determinant() == 0.0)
    {
      vtkErrorMacro("The volume matrix is singular.");
      return 1;
    }
    vtkMatrix4x4::Invert(this->VolumeMatrix, worldToData);
  }
  vtkNew<vtkMatrix4x4> toIndex;
  vtkMatrix4x4::Multiply4x4(input->GetPhysicalToIndexMatrix(), worldToData, toIndex);
  const int* extent = input->GetExtent();
  for (int r = 0; r < 3; ++r)
  {
    toIndex->SetElement(r, 3, toIndex->GetElement(r, 3) - extent[2 * r]);
  }
  auto toGrid = [&](const double w[3], double g[3], double h)
  {
    const double in[4] = { w[0], w[1], w[2], h };
    double out[4];
    toIndex->MultiplyPoint(in, out);
    std::copy(out, out + 3, g);
  };
  double o00[3], o10[3], o01[3], d[3];
  this->RayModel->GetPixelRay(0, 0, o00, d);
  this->RayModel->GetPixelRay(1, 0, o10, d);
  this->RayModel->GetPixelRay(0, 1, o01, d);
  double g10[3], g01[3];
  toGrid(o00, I.O, 1.0);
  toGrid(o10, g10, 1.0);
  toGrid(o01, g01, 1.0);
  toGrid(d, I.D, 0.0);
  vtkMath::Subtract(g10, I.O, I.EX);
  vtkMath::Subtract(g01, I.O, I.EY);
  for (int a = 0; a < 3; ++a)
  {
    I.Still[a] = I.D[a] == 0.0;
    I.InvD[a] = I.Still[a] ? 0.0 : 1.0 / I.D[a];
  }
  double columns[3][3];
  for (int a = 0; a < 3; ++a)
  {
    columns[a][0] = I.EX[a];
    columns[a][1] = I.EY[a];
    columns[a][2] = I.D[a];
  }
  vtkMath::Invert3x3(columns, I.Inverse);
  // Each pixel ray's chord through the box of the points.
  I.Chords.assign(2 * static_cast<size_t>(I.Width) * I.Height, 0.0);
  vtkSMPTools::For(0,
    I.Height,
    [&](vtkIdType j0, vtkIdType j1)
    {
      for (vtkIdType j = j0; j < j1; ++j)
      {
        for (int i = 0; i < I.Width; ++i)
        {
          double te = 0.0, tx = std::numeric_limits<double>::infinity();
          for (int a = 0; a < 3; ++a)
          {
            const double o = I.O[a] + i * I.EX[a] + j * I.EY[a];
            if (I.Still[a])
            {
              tx = (o >= 0.0 && o <= I.Cells[a]) ? tx : -1.0;
              continue;
            }
            const double t1 = -o * I.InvD[a], t2 = (I.Cells[a] - o) * I.InvD[a];
            te = std::max(te, std::min(t1, t2));
            tx = std::min(tx, std::max(t1, t2));
          }
          const size_t p = static_cast<size_t>(i) + static_cast<size_t>(I.Width) * j;
          I.Chords[2 * p] = te;
          I.Chords[2 * p + 1] = tx;
        }
      }
    });
  // Shading: the headlight (towards the camera) in data space, where normals are taken.
  I.Shading = this->VolumeProperty->GetShade(0) ? (this->ShadingMode == PRE_SHADING ? 2 : 1) : 0;
  if (I.Shading)
  {
    const double* m = input->GetPhysicalToIndexMatrix()->GetData();
    for (int r = 0; r < 3; ++r)
    {
      for (int k = 0; k < 3; ++k)
      {
        I.ToData[r][k] = m[4 * k + r]; // transposed: data gradient = M^T index gradient
      }
    }
    // Minus the view direction, taken back through the volume's placement (exact for rigid
    // placements; scaled ones tilt normals, as for any mapper shading in data space).
    double light[4] = { -d[0], -d[1], -d[2], 0.0 };
    worldToData->MultiplyPoint(light, light);
    std::copy(light, light + 3, I.Light);
    vtkMath::Normalize(I.Light);
    I.Ambient = static_cast<float>(this->VolumeProperty->GetAmbient(0));
    I.Diffuse = static_cast<float>(this->VolumeProperty->GetDiffuse(0));
    I.Specular = static_cast<float>(this->VolumeProperty->GetSpecular(0));
    I.Power = static_cast<float>(this->VolumeProperty->GetSpecularPower(0));
  }
  if (I.Shading == 2)
  {
    if (I.DirectionScalars != scalars || I.DirectionTime < scalars->GetMTime() ||
      I.Directions.size() != I.Bricks.size() ||
      !std::equal(&I.ToData[0][0], &I.ToData[0][0] + 9, &I.DirectionToData[0][0]))
    {
      // Once per volume: each point's quantized data-space normal.
      I.Directions.assign(I.Bricks.size(), static_cast<uint16_t>(Bins * Bins));
      vtkSMPTools::For(0,
        dims[2],
        [&](vtkIdType k0, vtkIdType k1)
        {
          for (int z = static_cast<int>(k0); z < k1; ++z)
          {
            for (int y = 0; y < dims[1]; ++y)
            {
              for (int x = 0; x < dims[0]; ++x)
              {
                float g[3];
                I.Gradient(x, y, z, g);
                double n[3];
                I.DataNormal(g, n);
                if (vtkMath::Normalize(n) > 0.0)
                {
                  I.Directions[I.Address(x, y, z)] = static_cast<uint16_t>(DirectionBin(n));
                }
              }
            }
          }
        });
      I.DirectionScalars = scalars;
      I.DirectionTime = scalars->GetMTime();
      std::copy(&I.ToData[0][0], &I.ToData[0][0] + 9, &I.DirectionToData[0][0]);
    }
    // Per frame: the reflectance map of the bins; the last entry has no normal (ambient).
    I.Reflectance.resize(2 * (Bins * Bins + 1));
    for (int bin = 0; bin < Bins * Bins; ++bin)
    {
      double n[3];
      BinDirection(bin, n);
      I.Lighting(
        std::abs(vtkMath::Dot(n, I.Light)), I.Reflectance[2 * bin], I.Reflectance[2 * bin + 1]);
    }
    I.Reflectance[2 * Bins * Bins] = I.Ambient;
    I.Reflectance[2 * Bins * Bins + 1] = 0.0f;
  }
  // Pre-integrated classification: the first-order table for one step over the data range.
  I.Preintegrated = this->Classification == PREINTEGRATED;
  if (I.Preintegrated)
  {
    this->SegmentTable->SetVolumeProperty(this->VolumeProperty);
    this->SegmentTable->SetSegmentLength(this->SampleDistance);
    this->SegmentTable->SetScalarRange(range);
    // At most 512^2 entries (4 MiB): on headsq-semi, the bench's one table above that,
    // 1024^2 (16 MiB) gave the same RMSE but missed the caches (6% slower per frame).
    this->SegmentTable->SetTableSize(vtkPreIntegrationTable::SuggestTableSize(
      scalars->GetDataType(), range, this->Sampler, 256, 512, 8.0)); // prepared by PrepareFrame
    if (!this->SegmentTable->Update())
    {
      return 1;
    }
    I.Segments = this->SegmentTable->GetTable()->GetPointer(0);
    I.SegmentEntries = this->SegmentTable->GetTableSize();
    I.SegmentInvStep = (I.SegmentEntries - 1) / (range[1] - range[0]);
  }
  I.Step = this->SampleDistance;
  I.Interleaved = this->InterleavedSampling;
  I.Removal = this->HiddenVolumeRemoval;
  I.Threshold = static_cast<float>(this->OpacityThreshold);
  I.FrameReady = true;

  // Tiles in parallel; each pixel is written by its tile only.
  const int tile = this->TileSize;
  const int tilesX = (I.Width + tile - 1) / tile, tilesY = (I.Height + tile - 1) / tile;
  // Leaves of LeafSize cells, rounded down to a power of two.
  int leafLevel = 0;
  while (leafLevel < MaxLeafLevel && (2 << leafLevel) <= this->LeafSize)
  {
    ++leafLevel;
  }
  I.LeafLevel = std::min(leafLevel, this->Octree->GetNumberOfLevels());
  vtkSMPThreadLocal<vtkIdType> nodes(0), samples(0);
  float* image = rgba->GetPointer(0);
  vtkSMPTools::For(0,
    static_cast<vtkIdType>(tilesX) * tilesY,
    1,
    [&](vtkIdType t0, vtkIdType t1)
    {
      TileWalker walker(I, this->Octree);
      walker.Image = image;
      for (vtkIdType t = t0; t < t1; ++t)
      {
        const int tx = static_cast<int>(t % tilesX), ty = static_cast<int>(t / tilesX);
        const int clip[4] = { tx * tile,
          std::min((tx + 1) * tile, I.Width) - 1,
          ty * tile,
          std::min((ty + 1) * tile, I.Height) - 1 };
        walker.Walk(clip);
      }
      nodes.Local() += walker.Nodes;
      samples.Local() += walker.Samples;
    });
  for (vtkIdType n : nodes)
  {
    this->NumberOfNodesVisited += n;
  }
  for (vtkIdType s : samples)
  {
    this->NumberOfSamples += s;
  }
  // Cells sampled, each once; the bits are cleared for the next frame.
  vtkSMPThreadLocal<vtkIdType> sampled(0);
  vtkSMPTools::For(0,
    static_cast<vtkIdType>(I.BrickTotal * BrickWords),
    [&](vtkIdType w0, vtkIdType w1)
    {
      vtkIdType count = 0;
      for (vtkIdType w = w0; w < w1; ++w)
      {
        const uint64_t bits = I.SampledBits[w].load(std::memory_order_relaxed);
        if (bits)
        {
          count += static_cast<vtkIdType>(std::bitset<64>(bits).count());
          I.SampledBits[w].store(0, std::memory_order_relaxed);
        }
      }
      sampled.Local() += count;
    });
  for (vtkIdType n : sampled)
  {
    this->NumberOfNonTransparentCells += n;
  }
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
vtkIdType vtkObjectOrderRayCaster::ComputeNonTransparentCells()
{
  const vtkInternals& I = *this->Internals;
  if (!I.FrameReady)
  {
    return -1;
  }
  TileWalker walker(I, this->Octree);
  walker.Render = false;
  walker.Removal = false;
  const int clip[4] = { 0, I.Width - 1, 0, I.Height - 1 };
  walker.Walk(clip);
  return walker.Cells;
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCaster::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "InterleavedSampling: " << this->InterleavedSampling << "\n";
  os << indent << "HiddenVolumeRemoval: " << this->HiddenVolumeRemoval << "\n";
  os << indent << "OpacityThreshold: " << this->OpacityThreshold << "\n";
  os << indent << "TileSize: " << this->TileSize << "\n";
  os << indent << "LeafSize: " << this->LeafSize << "\n";
  os << indent << "ShadingMode: " << this->ShadingMode << "\n";
  os << indent << "Classification: " << this->Classification << "\n";
  os << indent << "VolumeMatrix: " << this->VolumeMatrix << "\n";
  os << indent << "NumberOfNonTransparentCells: " << this->NumberOfNonTransparentCells << "\n";
  os << indent << "NumberOfNodesVisited: " << this->NumberOfNodesVisited << "\n";
  os << indent << "NumberOfSamples: " << this->NumberOfSamples << "\n";
  os << indent << "TableSize: " << this->TableSize << "\n";
}
