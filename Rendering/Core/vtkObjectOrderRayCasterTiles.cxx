// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkObjectOrderRayCasterTiles.h"

#include "vtkHierarchicalOcclusionMap.h"
#include "vtkMinMaxOctree.h"
#include "vtkObjectOrderRayCasterFrame.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
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

namespace
{
using Frame = vtkObjectOrderRayCasterFrame;
constexpr int BrickCells = vtkObjectOrderRayCasterBricks::BrickCells;
constexpr int BrickPoints = vtkObjectOrderRayCasterBricks::BrickPoints;
constexpr int BrickValues = vtkObjectOrderRayCasterBricks::BrickValues;
constexpr int BrickWords = vtkObjectOrderRayCasterBricks::BrickWords;

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

// The walk for any x86-64 processor, and (HOVR_WALKER_AVX2) the one for those with AVX2 and
// FMA. Each piece uses those before it, hence the order of the includes.
namespace generic
{
// The leaves.
#include "vtkObjectOrderRayCasterLeaf.txx"
// The sample loop.
#include "vtkObjectOrderRayCasterSamples.txx"
// The tile walker.
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
// The leaves.
#include "vtkObjectOrderRayCasterLeaf.txx"
// The sample loop.
#include "vtkObjectOrderRayCasterSamples.txx"
// The eight-lane sample loop.
#include "vtkObjectOrderRayCasterLanes.txx"
// The tile walker.
#include "vtkObjectOrderRayCasterWalker.txx"
}
#undef HOVR_WALKER_AVX2
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif
}

//------------------------------------------------------------------------------
bool vtkObjectOrderRayCasterTiles::HasAVX2()
{
#ifdef HOVR_AVX2_WALKER
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has;
#else
  return false;
#endif
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCasterTiles::Walk(const vtkObjectOrderRayCasterFrame& frame,
  const vtkMinMaxOctree* octree,
  bool avx2,
  int tileSize,
  vtkIdType begin,
  vtkIdType end,
  const vtkTypeBool& abort,
  float* image,
  vtkIdType& nodes,
  vtkIdType& samples)
{
  const int width = frame.Rays.Width, height = frame.Rays.Height;
  const int tilesX = (width + tileSize - 1) / tileSize;
  const int* volume = frame.Rays.VolumePixels;
  vtkSMPThreadLocal<vtkIdType> tileNodes(0), tileSamples(0);
  auto walk = [&](auto* walkerType)
  {
    using Walker = typename std::remove_pointer<decltype(walkerType)>::type;
    vtkSMPTools::For(begin,
      end,
      1,
      [&](vtkIdType t0, vtkIdType t1)
      {
        Walker walker(frame, octree);
        walker.Image = image;
        for (vtkIdType t = t0; t < t1; ++t)
        {
          const int tx = static_cast<int>(t % tilesX), ty = static_cast<int>(t / tilesX);
          const int clip[4] = { tx * tileSize,
            std::min((tx + 1) * tileSize, width) - 1,
            ty * tileSize,
            std::min((ty + 1) * tileSize, height) - 1 };
          if (!abort && clip[1] >= volume[0] && clip[0] <= volume[1] && clip[3] >= volume[2] &&
            clip[2] <= volume[3])
          {
            walker.Walk(clip); // writes every pixel of the tile
          }
          else
          {
            for (int py = clip[2]; py <= clip[3]; ++py)
            {
              float* row = image + 4 * (static_cast<size_t>(width) * py + clip[0]);
              std::fill(row, row + 4 * (clip[1] - clip[0] + 1), 0.0f);
            }
          }
        }
        tileNodes.Local() += walker.Nodes;
        tileSamples.Local() += walker.Samples;
      });
  };
#ifdef HOVR_AVX2_WALKER
  if (avx2)
  {
    walk(static_cast<avx2::TileWalker*>(nullptr));
  }
  else
#else
  (void)avx2;
#endif
  {
    walk(static_cast<generic::TileWalker*>(nullptr));
  }
  for (vtkIdType n : tileNodes)
  {
    nodes += n;
  }
  for (vtkIdType s : tileSamples)
  {
    samples += s;
  }
}

//------------------------------------------------------------------------------
vtkIdType vtkObjectOrderRayCasterTiles::CountNonTransparentCells(
  const vtkObjectOrderRayCasterFrame& frame,
  const vtkMinMaxOctree* octree)
{
  generic::TileWalker walker(frame, octree); // counting only: no sample loop
  walker.Render = false;
  walker.Removal = false;
  const int clip[4] = { 0, frame.Rays.Width - 1, 0, frame.Rays.Height - 1 };
  walker.Walk(clip);
  return walker.Cells;
}
