// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkObjectOrderRayCasterBricks.h"

#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkObjectOrderRayCasterClassification.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include <bitset>

//------------------------------------------------------------------------------
int vtkObjectOrderRayCasterBricks::BrickCountAlong(int points)
{
  return std::max((points - 2) / BrickCells + 1, 1);
}

//------------------------------------------------------------------------------
bool vtkObjectOrderRayCasterBricks::IsBuiltFor(vtkDataArray* scalars, const int dims[3]) const
{
  return this->Scalars == scalars && this->ScalarsTime >= scalars->GetMTime() &&
    std::equal(dims, dims + 3, this->Dims);
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCasterBricks::Build(vtkDataArray* scalars, const int dims[3])
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

//------------------------------------------------------------------------------
void vtkObjectOrderRayCasterBricks::Release()
{
  std::vector<float>().swap(this->Bricks);
  for (auto& address : this->AxisAddress)
  {
    std::vector<size_t>().swap(address);
  }
  this->VisibleBits.reset();
  this->SampledBits.reset();
  this->VisibleVersions.reset();
  this->BrickTotal = 0;
  std::fill(this->Dims, this->Dims + 3, 0);
  this->Scalars = nullptr;
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCasterBricks::NewClassification()
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

//------------------------------------------------------------------------------
// The ranges of all cells are found by separable passes: pairs of points along x, then
// pairs of those along y, then along z.
void vtkObjectOrderRayCasterBricks::BrickVisibility(size_t b,
  const int bc[3],
  const vtkObjectOrderRayCasterClassification& classification,
  uint64_t bits[BrickWords]) const
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
        bool visible = classification.Visible(
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

//------------------------------------------------------------------------------
vtkIdType vtkObjectOrderRayCasterBricks::CountSampledCells()
{
  vtkSMPThreadLocal<vtkIdType> sampled(0);
  vtkSMPTools::For(0,
    static_cast<vtkIdType>(this->BrickTotal * BrickWords),
    [&](vtkIdType w0, vtkIdType w1)
    {
      vtkIdType count = 0;
      for (vtkIdType w = w0; w < w1; ++w)
      {
        const uint64_t bits = this->SampledBits[w].load(std::memory_order_relaxed);
        if (bits)
        {
          count += static_cast<vtkIdType>(std::bitset<64>(bits).count());
          this->SampledBits[w].store(0, std::memory_order_relaxed);
        }
      }
      sampled.Local() += count;
    });
  vtkIdType total = 0;
  for (vtkIdType n : sampled)
  {
    total += n;
  }
  return total;
}

//------------------------------------------------------------------------------
size_t vtkObjectOrderRayCasterBricks::GetMemorySize() const
{
  return this->Bricks.size() * sizeof(float) +
    this->BrickTotal * (2 * BrickWords * sizeof(uint64_t) + sizeof(uint32_t));
}
