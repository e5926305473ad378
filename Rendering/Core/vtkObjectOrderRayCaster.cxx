// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkObjectOrderRayCaster.h"

#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkErrorForwarder.h"
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
#include <new>
#include <type_traits>
#include <vector>

// SSE2 (every x86-64 compiler): the sample loop's small vectors; a scalar fallback elsewhere.
#if defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2)
#define HOVR_SSE2 1
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h> // the AVX2 copy of the sample loop
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

// Bricks along an axis of `points` points (at least one, for a flat axis).
int BrickCountAlong(int points)
{
  return std::max((points - 2) / BrickCells + 1, 1);
}
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
  float Threshold = 0.996f;
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
  // The pixels whose rays can meet the grid's box (empty: x0 > x1); the tiles outside it
  // keep the output's zeros.
  int VolumePixels[4] = { 0, -1, 0, -1 };
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
      this->BrickCount[a] = BrickCountAlong(dims[a]);
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

  // After an allocation failed: the copies of the volume freed (not just emptied), so that
  // the memory goes back and the next update starts again from the scalars.
  void ReleaseVolume()
  {
    std::vector<float>().swap(this->Bricks);
    std::vector<uint16_t>().swap(this->Directions);
    for (auto& address : this->AxisAddress)
    {
      std::vector<size_t>().swap(address);
    }
    this->VisibleBits.reset();
    this->SampledBits.reset();
    this->VisibleVersions.reset();
    this->BrickTotal = 0;
    std::fill(this->Dims, this->Dims + 3, 0);
    this->Scalars = this->DirectionScalars = nullptr;
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

  // Where pixel (i, j)'s ray enters and leaves the box of the points (t): te > tx, or tx < 0,
  // when it misses.
  void Chord(int i, int j, double& te, double& tx) const
  {
    te = 0.0;
    tx = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a)
    {
      const double o = this->O[a] + i * this->EX[a] + j * this->EY[a];
      if (this->Still[a])
      {
        tx = (o >= 0.0 && o <= this->Cells[a]) ? tx : -1.0;
        continue;
      }
      const double t1 = -o * this->InvD[a], t2 = (this->Cells[a] - o) * this->InvD[a];
      te = std::max(te, std::min(t1, t2));
      tx = std::min(tx, std::max(t1, t2));
    }
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
    // NaN (from a degenerate frame) counts as the whole clip rectangle: conservative.
    auto ceilIn = [](double x, int lo, int hi)
    {
      x = std::isnan(x) ? lo : std::min(std::max(x, lo - 1.0), hi + 1.0);
      const int n = static_cast<int>(x); // truncates towards 0
      return n + (n < x ? 1 : 0);
    };
    auto floorIn = [](double x, int lo, int hi)
    {
      x = std::isnan(x) ? hi : std::min(std::max(x, lo - 1.0), hi + 1.0);
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

// The sample loop's common case, so that the compiler lays out its rare cases out of line.
#if defined(__GNUC__) || defined(__clang__)
#define HOVR_LIKELY(condition) __builtin_expect(!!(condition), 1)
#else
#define HOVR_LIKELY(condition) (condition)
#endif

// A hint that the cache line at an address will be read soon.
#if defined(__GNUC__) || defined(__clang__)
#define HOVR_PREFETCH(address) __builtin_prefetch(address)
#elif defined(HOVR_SSE2)
#define HOVR_PREFETCH(address) _mm_prefetch(reinterpret_cast<const char*>(address), _MM_HINT_T0)
#else
#define HOVR_PREFETCH(address) ((void)(address))
#endif

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

// The tiles' walk and their sample loop, compiled twice: for any x86-64 processor (SSE2) and,
// with GCC or Clang on x86-64, for those with AVX2 and FMA, where fused multiply-adds shorten
// the chains of dependent operations of a sample and the unshaded rays of a leaf are sampled
// eight at a time (HOVR_WALKER_AVX2: TileWalker::RunLanes). Everything in the file has
// internal linkage, so neither copy replaces the other (no weak symbol of the object holds AVX
// code).
namespace generic
{
#include "vtkObjectOrderRayCasterWalker.txx"
}
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define HOVR_AVX2_WALKER 1
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,fma"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#endif
#define HOVR_WALKER_AVX2 1
namespace avx2
{
#include "vtkObjectOrderRayCasterWalker.txx"
}
#undef HOVR_WALKER_AVX2
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif

// Whether the processor runs the AVX2 copy.
bool HasAVX2()
{
#ifdef HOVR_AVX2_WALKER
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has;
#else
  return false;
#endif
}
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
  // The table's and octree's errors reach the caster's observers (the Python package's).
  vtkErrorForwarder::Forward(this->SegmentTable, this);
  vtkErrorForwarder::Forward(this->Octree, this);
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
  this->LastUpdateOutOfMemory = false;
  this->NumberOfNonTransparentCells = this->NumberOfNodesVisited = this->NumberOfSamples = 0;
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  // The image is cleared by the walk where no tile writes it, so that no pixel is written
  // twice, or all of it when the frame stops before.
  vtkFloatArray* rgba = this->InitializeOutput(vtkImageData::GetData(outputVector), false);
  if (!rgba)
  {
    return 1;
  }
  struct ClearUnlessWalked
  {
    vtkFloatArray* Image;
    bool Walked = false;
    ~ClearUnlessWalked()
    {
      if (!this->Walked)
      {
        this->Image->FillValue(0.0f);
      }
    }
  } clearImage{ rgba };
  int dims[3];
  vtkDataArray* scalars = this->PrepareFrame(input, inputVector, dims);
  if (!scalars)
  {
    return 1;
  }
  if (!this->CheckSampleDistance(input, this->SampleDistance, this->MaximumSamplesPerRay))
  {
    return 1;
  }
  const double diagonal = input->GetLength(); // of the bounds
  const double* spacing = input->GetSpacing();
  const double voxel =
    std::min({ std::abs(spacing[0]), std::abs(spacing[1]), std::abs(spacing[2]) });
  if (this->SampleDistance < 1e-5 * voxel)
  {
    vtkErrorMacro("The sample distance " << this->SampleDistance << " is below 1e-5 voxel ("
                                         << voxel
                                         << "), where the walker's float positions lose it.");
    return 1;
  }
  if (!this->GetCamera()->GetParallelProjection())
  {
    vtkErrorMacro("Object-order ray casting needs a parallel projection (every cell projects "
                  "to the same shape); the camera has a perspective one.");
    return 1;
  }

  double range[2];
  scalars->GetFiniteRange(range, 0); // not empty: checked by PrepareFrame
  if (std::max(std::abs(range[0]), std::abs(range[1])) > VTK_FLOAT_MAX)
  {
    vtkErrorMacro("The scalar range [" << range[0] << ", " << range[1]
                                       << "] exceeds float range, in which the caster stores the "
                                          "volume; rescale the values.");
    return 1;
  }

  // The volume: bricks and octree, once per data. Their allocations are the caster's only
  // large ones (about 7 bytes per point): when memory runs out, an error and an empty image
  // rather than an exception through the pipeline.
  if (I.Scalars != scalars || I.ScalarsTime < scalars->GetMTime() ||
    !std::equal(dims, dims + 3, I.Dims))
  {
    try
    {
      I.BuildBricks(scalars, dims);
      if (!this->Octree->Build(scalars, dims))
      {
        I.ReleaseVolume();
        return 1;
      }
    }
    catch (const std::bad_alloc&)
    {
      this->OutOfMemory(dims, "the float bricks and octree");
      return 1;
    }
    I.Scalars = scalars;
    I.ScalarsTime = scalars->GetMTime();
  }
  this->UpdateProgress(0.1);

  // Classification table over the data range.
  if (!(range[1] > range[0]))
  {
    // A relative width: range[0] + 1 rounds back to range[0] beyond 2^53.
    range[1] = range[0] + std::max(1.0, std::abs(range[0]) * 1e-6);
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
    const double* m = this->VolumeMatrix->GetData();
    const double determinant = this->VolumeMatrix->Determinant();
    if (!std::all_of(m, m + 16, [](double x) { return std::isfinite(x); }) ||
      !(std::abs(determinant) > 0.0) || !std::isfinite(determinant))
    {
      vtkErrorMacro(
        "The volume matrix must be finite and invertible (determinant " << determinant << ").");
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
  // Rays start at the camera's plane; a camera far from the volume puts sample indices beyond
  // 2^53, where n + 1 == n. Starting them a whole number of steps later, no nearer than the
  // box's nearest corner, keeps the same samples and small indices.
  double nearest = VTK_DOUBLE_MAX;
  for (int corner = 0; corner < 8; ++corner)
  {
    double c[3];
    for (int a = 0; a < 3; ++a)
    {
      c[a] = ((corner >> a) & 1 ? I.Cells[a] : 0.0) - I.O[a];
    }
    nearest = std::min(nearest, vtkMath::Dot(I.Inverse[2], c));
  }
  if (nearest > this->SampleDistance && std::isfinite(nearest))
  {
    const double skip = std::floor(nearest / this->SampleDistance) * this->SampleDistance;
    for (int a = 0; a < 3; ++a)
    {
      I.O[a] += skip * I.D[a];
    }
  }
  // The pixels whose rays can meet the box of the points: the tiles outside them are left
  // as the output was initialized (transparent), and each tile finds its own pixels' chords.
  const double boxLo[3] = { 0.0, 0.0, 0.0 };
  const double boxHi[3] = { static_cast<double>(I.Cells[0]),
    static_cast<double>(I.Cells[1]),
    static_cast<double>(I.Cells[2]) };
  const int wholeImage[4] = { 0, I.Width - 1, 0, I.Height - 1 };
  if (!I.Rectangle(boxLo, boxHi, wholeImage, I.VolumePixels))
  {
    std::fill(I.VolumePixels, I.VolumePixels + 4, 0);
    I.VolumePixels[1] = I.VolumePixels[3] = -1;
  }
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
      try
      {
        I.Directions.assign(I.Bricks.size(), static_cast<uint16_t>(Bins * Bins));
      }
      catch (const std::bad_alloc&)
      {
        this->OutOfMemory(dims, "the quantized normals (pre-shading)");
        return 1;
      }
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
    // At most 512^2 entries (4 MiB): a finer table falls out of the caches the sample loop
    // relies on, for little gain in accuracy.
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
  // A frame expected to take many samples (every pixel of the volume's rectangle through the
  // whole diagonal) is walked in parts, with progress in between: progress events come from
  // this thread only.
  const vtkIdType tiles = static_cast<vtkIdType>(tilesX) * tilesY;
  const double expectedSamples = (I.VolumePixels[1] - I.VolumePixels[0] + 1.0) *
    (I.VolumePixels[3] - I.VolumePixels[2] + 1.0) * diagonal / this->SampleDistance;
  const vtkIdType parts = expectedSamples > (1 << 28) ? std::min<vtkIdType>(tiles, 20) : 1;
  auto walk = [&](auto* walkerType)
  {
    using Walker = typename std::remove_pointer<decltype(walkerType)>::type;
    for (vtkIdType part = 0; part < parts; ++part)
    {
      vtkSMPTools::For(part * tiles / parts,
        (part + 1) * tiles / parts,
        1,
        [&](vtkIdType t0, vtkIdType t1)
        {
          Walker walker(I, this->Octree);
          walker.Image = image;
          for (vtkIdType t = t0; t < t1; ++t)
          {
            const int tx = static_cast<int>(t % tilesX), ty = static_cast<int>(t / tilesX);
            const int clip[4] = { tx * tile,
              std::min((tx + 1) * tile, I.Width) - 1,
              ty * tile,
              std::min((ty + 1) * tile, I.Height) - 1 };
            if (!this->AbortExecute && clip[1] >= I.VolumePixels[0] &&
              clip[0] <= I.VolumePixels[1] && clip[3] >= I.VolumePixels[2] &&
              clip[2] <= I.VolumePixels[3])
            {
              walker.Walk(clip); // writes every pixel of the tile
            }
            else
            {
              for (int py = clip[2]; py <= clip[3]; ++py)
              {
                float* row = image + 4 * (static_cast<size_t>(I.Width) * py + clip[0]);
                std::fill(row, row + 4 * (clip[1] - clip[0] + 1), 0.0f);
              }
            }
          }
          nodes.Local() += walker.Nodes;
          samples.Local() += walker.Samples;
        });
      if (parts > 1)
      {
        this->UpdateProgress(0.1 + 0.9 * static_cast<double>(part + 1) / parts);
      }
    }
  };
  clearImage.Walked = true;
  this->LastInstructionSet =
    this->InstructionSet == INSTRUCTIONS_SSE2 || !HasAVX2() ? INSTRUCTIONS_SSE2 : INSTRUCTIONS_AVX2;
  if (this->InstructionSet == INSTRUCTIONS_AVX2 && !HasAVX2())
  {
    vtkWarningMacro("The AVX2 sample loop was asked for, but this processor (or this build) "
                    "lacks AVX2 and FMA; rendering with the SSE2 one.");
  }
#ifdef HOVR_AVX2_WALKER
  if (this->LastInstructionSet == INSTRUCTIONS_AVX2)
  {
    walk(static_cast<avx2::TileWalker*>(nullptr));
  }
  else
#endif
  {
    walk(static_cast<generic::TileWalker*>(nullptr));
  }
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
  if (!this->GetAbortExecute())
  {
    this->WarnIfTransparent(rgba);
  }
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCaster::OutOfMemory(const int dims[3], const char* what)
{
  vtkInternals& I = *this->Internals;
  I.ReleaseVolume();
  this->Octree->Initialize();
  this->LastUpdateOutOfMemory = true;
  // What the copies need: bricks of 8^3 cells with their far faces, in float.
  double bricks = BrickValues * sizeof(float);
  for (int a = 0; a < 3; ++a)
  {
    bricks *= BrickCountAlong(dims[a]);
  }
  vtkErrorMacro("Not enough memory for " << what << " of the " << dims[0] << " x " << dims[1]
                                         << " x " << dims[2] << " volume (the bricks alone take "
                                         << std::ceil(bricks / (1 << 20))
                                         << " MiB); the image is empty.");
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCaster::GetLastVolumePixels(int rect[4]) const
{
  static const int none[4] = { 0, -1, 0, -1 };
  const vtkInternals& I = *this->Internals;
  const int* pixels = I.FrameReady ? I.VolumePixels : none;
  std::copy(pixels, pixels + 4, rect);
}

//------------------------------------------------------------------------------
vtkIdType vtkObjectOrderRayCaster::ComputeNonTransparentCells()
{
  const vtkInternals& I = *this->Internals;
  if (!I.FrameReady)
  {
    return -1;
  }
  generic::TileWalker walker(I, this->Octree); // counting only: no sample loop
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
  os << indent << "InstructionSet: " << this->InstructionSet << "\n";
  os << indent << "LastInstructionSet: " << this->LastInstructionSet << "\n";
  os << indent << "ShadingMode: " << this->ShadingMode << "\n";
  os << indent << "Classification: " << this->Classification << "\n";
  os << indent << "VolumeMatrix: " << this->VolumeMatrix << "\n";
  os << indent << "NumberOfNonTransparentCells: " << this->NumberOfNonTransparentCells << "\n";
  os << indent << "NumberOfNodesVisited: " << this->NumberOfNodesVisited << "\n";
  os << indent << "NumberOfSamples: " << this->NumberOfSamples << "\n";
  os << indent << "TableSize: " << this->TableSize << "\n";
  os << indent << "LastUpdateOutOfMemory: " << this->LastUpdateOutOfMemory << "\n";
}
