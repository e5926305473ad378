// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkGridRayTraversal: the cells a ray crosses, in order, with contiguous parameter intervals
// that add up to the chord; special rays (axis-aligned, through edges and corners, on faces,
// from inside, negative directions, misses, one-cell grids) and random rays against brute
// force sampling. Then the paper's Figure 3 in float on a 256^3 grid: the integer-based
// traversal against an incremental Amanatides-Woo walk, error at every plane crossing.
#include "vtkGridRayTraversal.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"

#include "hovrTestUtilities.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace
{
hovrTest::Checker check;

struct Segment
{
  std::array<int, 3> Cell;
  double T0;
  double T1;
};

// All segments of a ray; an empty list when Initialize() reports a miss.
std::vector<Segment> Traverse(const int dims[3],
  const double o[3],
  const double v[3],
  double tmin = -std::numeric_limits<double>::infinity(),
  double tmax = std::numeric_limits<double>::infinity())
{
  std::vector<Segment> segments;
  vtkGridRayTraversal walk;
  if (!walk.Initialize(dims, o, v, tmin, tmax))
  {
    return segments;
  }
  Segment s;
  int cell[3];
  while (walk.Next(cell, s.T0, s.T1))
  {
    s.Cell = { cell[0], cell[1], cell[2] };
    segments.push_back(s);
    if (segments.size() > 100000)
    {
      break; // a runaway walk is a failure, reported by the callers' checks
    }
  }
  return segments;
}

std::string Describe(const std::vector<Segment>& segments)
{
  std::ostringstream os;
  for (const Segment& s : segments)
  {
    os << " (" << s.Cell[0] << "," << s.Cell[1] << "," << s.Cell[2] << ")[" << s.T0 << "," << s.T1
       << "]";
  }
  return os.str();
}

// Independent slab clipping against [0, dims-1]^3 within [tmin, tmax]: the reference chord.
bool ReferenceClip(const int dims[3], const double o[3], const double v[3], double& t0, double& t1)
{
  for (int a = 0; a < 3; ++a)
  {
    const double hi = dims[a] - 1.0;
    if (v[a] == 0.0)
    {
      if (o[a] < 0.0 || o[a] > hi)
      {
        return false;
      }
      continue;
    }
    const double ta = (0.0 - o[a]) / v[a], tb = (hi - o[a]) / v[a];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  return t0 < t1;
}

// Structural checks valid for any ray: the intervals start at the entry, are contiguous and
// of positive length, end at the exit, and consecutive cells are neighbours inside the grid
// (sharing a face, or an edge or corner where the ray crosses two or three planes at once).
void CheckStructure(const std::vector<Segment>& segments,
  const int dims[3],
  double entry,
  double exit,
  const std::string& label)
{
  if (!check(!segments.empty(), label + ": at least one cell"))
  {
    return;
  }
  const double scale = std::max({ 1.0, std::abs(entry), std::abs(exit) });
  check.Near(segments.front().T0, entry, 1e-12 * scale, label + ": first interval starts at entry");
  check.Near(segments.back().T1, exit, 1e-12 * scale, label + ": last interval ends at exit");
  double sum = 0.0;
  for (size_t n = 0; n < segments.size(); ++n)
  {
    const Segment& s = segments[n];
    sum += s.T1 - s.T0;
    bool inside = true;
    for (int a = 0; a < 3; ++a)
    {
      inside = inside && s.Cell[a] >= 0 && s.Cell[a] <= dims[a] - 2;
    }
    check(inside, label + ": cell inside the grid," + Describe({ s }));
    check(s.T1 > s.T0, label + ": positive interval," + Describe({ s }));
    if (n > 0)
    {
      // Contiguous: each interval starts exactly where the previous one ended.
      check(s.T0 == segments[n - 1].T1,
        label + ": contiguous intervals," + Describe({ segments[n - 1], s }));
      int moved = 0, farthest = 0;
      for (int a = 0; a < 3; ++a)
      {
        const int d = std::abs(s.Cell[a] - segments[n - 1].Cell[a]);
        moved += d;
        farthest = std::max(farthest, d);
      }
      check(moved >= 1 && farthest == 1,
        label + ": consecutive cells are neighbours," + Describe({ segments[n - 1], s }));
    }
  }
  check.Near(sum, exit - entry, 1e-12 * scale, label + ": interval lengths add up to the chord");
}

// Expected cells and intervals exactly (all values here are small dyadic numbers).
void CheckExact(const std::vector<Segment>& segments,
  const std::vector<Segment>& expected,
  const std::string& label)
{
  bool ok = segments.size() == expected.size();
  for (size_t n = 0; ok && n < segments.size(); ++n)
  {
    ok = segments[n].Cell == expected[n].Cell && segments[n].T0 == expected[n].T0 &&
      segments[n].T1 == expected[n].T1;
  }
  check(ok, label + ": got" + Describe(segments) + ", expected" + Describe(expected));
}
}

int TestGridRayTraversal(int, char*[])
{
  const double inf = std::numeric_limits<double>::infinity();

  //----------------------------------------------------------------------------
  // Axis-aligned rays, positive and negative, through the middle of cells.
  {
    const int dims[3] = { 5, 4, 3 };
    const double o[3] = { -1.0, 1.5, 0.5 }, v[3] = { 1.0, 0.0, 0.0 };
    CheckExact(Traverse(dims, o, v),
      { { { 0, 1, 0 }, 1, 2 },
        { { 1, 1, 0 }, 2, 3 },
        { { 2, 1, 0 }, 3, 4 },
        { { 3, 1, 0 }, 4, 5 } },
      "+x ray");
    const double on[3] = { 10.0, 1.5, 0.5 }, vn[3] = { -2.0, 0.0, 0.0 };
    CheckExact(Traverse(dims, on, vn),
      { { { 3, 1, 0 }, 3, 3.5 },
        { { 2, 1, 0 }, 3.5, 4 },
        { { 1, 1, 0 }, 4, 4.5 },
        { { 0, 1, 0 }, 4.5, 5 } },
      "-x ray with speed 2");
    const double oz[3] = { 2.25, 0.75, 7.0 }, vz[3] = { 0.0, 0.0, -0.5 };
    CheckExact(Traverse(dims, oz, vz),
      { { { 2, 0, 1 }, 10, 12 }, { { 2, 0, 0 }, 12, 14 } },
      "-z ray with speed 0.5");
    const double oy[3] = { 0.5, -3.0, 1.5 }, vy[3] = { 0.0, 1.0, 0.0 };
    CheckExact(Traverse(dims, oy, vy),
      { { { 0, 0, 1 }, 3, 4 }, { { 0, 1, 1 }, 4, 5 }, { { 0, 2, 1 }, 5, 6 } },
      "+y ray");
  }

  //----------------------------------------------------------------------------
  // Through corners and edges: tied axes step together, straight to the diagonal cell.
  {
    const int dims[3] = { 4, 4, 4 };
    const double o[3] = { -1.0, -1.0, -1.0 }, v[3] = { 1.0, 1.0, 1.0 };
    const auto all = Traverse(dims, o, v);
    CheckStructure(all, dims, 1.0, 4.0, "main diagonal");
    CheckExact(all,
      { { { 0, 0, 0 }, 1, 2 }, { { 1, 1, 1 }, 2, 3 }, { { 2, 2, 2 }, 3, 4 } },
      "main diagonal");
    const double on[3] = { 4.0, 4.0, 4.0 }, vn[3] = { -1.0, -1.0, -1.0 };
    CheckExact(Traverse(dims, on, vn),
      { { { 2, 2, 2 }, 1, 2 }, { { 1, 1, 1 }, 2, 3 }, { { 0, 0, 0 }, 3, 4 } },
      "reversed main diagonal");
    // Along an edge line x = y in the plane z = 1.5: crosses the edges x = y = 1, 2.
    const double oe[3] = { 0.0, 0.0, 1.5 }, ve[3] = { 1.0, 1.0, 0.0 };
    const auto edge = Traverse(dims, oe, ve);
    CheckStructure(edge, dims, 0.0, 3.0, "x = y diagonal");
    CheckExact(edge,
      { { { 0, 0, 1 }, 0, 1 }, { { 1, 1, 1 }, 1, 2 }, { { 2, 2, 1 }, 2, 3 } },
      "x = y diagonal");
    // Anti-diagonal in x, y through the edges x + y = 3.
    const double oa[3] = { 0.0, 3.0, 0.25 }, va[3] = { 1.0, -1.0, 0.0 };
    const auto anti = Traverse(dims, oa, va);
    CheckStructure(anti, dims, 0.0, 3.0, "anti-diagonal");
    CheckExact(anti,
      { { { 0, 2, 0 }, 0, 1 }, { { 1, 1, 0 }, 1, 2 }, { { 2, 0, 0 }, 2, 3 } },
      "anti-diagonal");
  }

  //----------------------------------------------------------------------------
  // Rays parallel to a face and lying exactly on a grid plane: interior plane (either side is
  // a valid cell, but one consistently), boundary planes (the only cell on that side).
  {
    const int dims[3] = { 4, 3, 3 };
    const double v[3] = { 1.0, 0.0, 0.0 };
    auto cellsAlongX = [&](int cy, int cz)
    {
      std::vector<Segment> expected;
      for (int i = 0; i < 3; ++i)
      {
        expected.push_back({ { i, cy, cz }, static_cast<double>(i), i + 1.0 });
      }
      return expected;
    };
    const double interior[3] = { 0.0, 1.0, 0.5 };
    const auto onPlane = Traverse(dims, interior, v);
    CheckStructure(onPlane, dims, 0.0, 3.0, "ray on the interior plane y = 1");
    const int cy = onPlane.empty() ? -1 : onPlane.front().Cell[1];
    check(cy == 0 || cy == 1, "ray on y = 1 walks a neighbouring row of cells");
    CheckExact(onPlane, cellsAlongX(cy, 0), "ray on the interior plane y = 1");
    const double low[3] = { 0.0, 0.0, 0.5 }, high[3] = { 0.0, 2.0, 2.0 };
    CheckExact(Traverse(dims, low, v), cellsAlongX(0, 0), "ray on the boundary plane y = 0");
    CheckExact(Traverse(dims, high, v), cellsAlongX(1, 1), "ray on the boundary edge y = 2, z = 2");
    const double outside[3] = { 0.0, 2.0 + 1e-12, 0.5 }, below[3] = { 0.0, -1e-12, 0.5 };
    check(Traverse(dims, outside, v).empty(), "ray parallel to and just above y = 2 misses");
    check(Traverse(dims, below, v).empty(), "ray parallel to and just below y = 0 misses");
  }

  //----------------------------------------------------------------------------
  // Rays from inside (t clipped at tmin = 0), clipped by tmax, and misses.
  {
    const int dims[3] = { 4, 4, 4 };
    const double o[3] = { 1.5, 1.25, 1.75 }, v[3] = { 1.0, 0.0, -0.5 };
    vtkGridRayTraversal walk;
    check(walk.Initialize(dims, o, v, 0.0, inf), "ray from inside is accepted");
    check(walk.GetEntry() == 0.0 && walk.GetExit() == 1.5, "ray from inside: interval [0, 1.5]");
    CheckExact(Traverse(dims, o, v, 0.0, inf),
      { { { 1, 1, 1 }, 0, 0.5 }, { { 2, 1, 1 }, 0.5, 1.5 } },
      "ray from inside");
    CheckExact(Traverse(dims, o, v, 0.0, 0.25),
      { { { 1, 1, 1 }, 0, 0.25 } },
      "ray from inside clipped by tmax within one cell");
    CheckExact(Traverse(dims, o, v, -1.0, 0.75),
      { { { 0, 1, 2 }, -1, -0.5 }, { { 1, 1, 1 }, -0.5, 0.5 }, { { 2, 1, 1 }, 0.5, 0.75 } },
      "ray clipped to [-1, 0.75]");

    const double away[3] = { -1.0, 1.0, 1.0 }, vAway[3] = { -1.0, 0.2, 0.0 };
    check(Traverse(dims, away, vAway, 0.0, inf).empty(), "ray pointing away from the box misses");
    const double past[3] = { -1.0, 5.0, 1.0 }, vPast[3] = { 1.0, 0.0, 0.3 };
    check(Traverse(dims, past, vPast).empty(), "ray passing beside the box misses");
    const double shortRay[3] = { -3.0, 1.0, 1.0 }, vShort[3] = { 1.0, 0.0, 0.0 };
    check(Traverse(dims, shortRay, vShort, 0.0, 2.5).empty(), "ray ending before the box misses");
    const double zero[3] = { 0.0, 0.0, 0.0 };
    check(Traverse(dims, o, zero, 0.0, 1.0).size() <= 1, "zero direction does not loop");
    const int flat[3] = { 4, 1, 4 };
    check(Traverse(flat, o, v).empty(), "a grid with one point along an axis has no cells");

    double t0 = 0.0, t1 = 10.0;
    const double lo[3] = { 1, 1, 1 }, hi[3] = { 2, 3, 4 }, p[3] = { 0, 2, 2 }, d[3] = { 2, 0, 1 };
    check(vtkGridRayTraversal::ClipToBox(lo, hi, p, d, t0, t1) && t0 == 0.5 && t1 == 1.0,
      "ClipToBox narrows [0, 10] to [0.5, 1]");
  }

  //----------------------------------------------------------------------------
  // Grids of 2 points along some axes: a single cell across those axes.
  {
    const int dims[3] = { 2, 2, 2 };
    const double o[3] = { -0.5, 0.3, 0.6 }, v[3] = { 1.0, 0.1, -0.2 };
    CheckExact(Traverse(dims, o, v), { { { 0, 0, 0 }, 0.5, 1.5 } }, "one-cell grid");
    const int slab[3] = { 2, 5, 2 };
    const double os[3] = { 0.5, 4.5, 0.5 }, vs[3] = { 0.0, -1.0, 0.0 };
    CheckExact(Traverse(slab, os, vs),
      { { { 0, 3, 0 }, 0.5, 1.5 },
        { { 0, 2, 0 }, 1.5, 2.5 },
        { { 0, 1, 0 }, 2.5, 3.5 },
        { { 0, 0, 0 }, 3.5, 4.5 } },
      "2 x 5 x 2 grid");
  }

  //----------------------------------------------------------------------------
  // Random rays against brute force: at many points along the chord, the cell containing the
  // point (floor of its coordinates, the far faces belonging to the last cell) must be the
  // cell of the interval containing that t; the chord itself comes from an independent clip.
  {
    vtkNew<vtkMinimalStandardRandomSequence> random;
    random->SetSeed(1234);
    auto next = [&]()
    {
      random->Next();
      return random->GetValue();
    };
    int hits = 0, mismatches = 0;
    for (int trial = 0; trial < 3000; ++trial)
    {
      const int dims[3] = { 2 + static_cast<int>(6 * next()),
        2 + static_cast<int>(6 * next()),
        2 + static_cast<int>(6 * next()) };
      double o[3], v[3];
      for (int a = 0; a < 3; ++a)
      {
        o[a] = -2.0 + (dims[a] + 3.0) * next();
        // Half of the rays aim at a point of the box, the others go anywhere.
        const double target = (dims[a] - 1.0) * next();
        v[a] = trial % 2 ? target - o[a] : 2.0 * next() - 1.0;
        if (trial % 7 == a)
        {
          v[a] = 0.0; // rays parallel to a pair of faces
        }
      }
      if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0)
      {
        continue;
      }
      const double tmin = trial % 3 == 0 ? 0.0 : -inf;
      double t0 = tmin, t1 = inf;
      const bool expectHit = ReferenceClip(dims, o, v, t0, t1);
      const auto segments = Traverse(dims, o, v, tmin, inf);
      std::ostringstream label;
      label << "random ray " << trial << " (dims " << dims[0] << "x" << dims[1] << "x" << dims[2]
            << ", origin " << o[0] << " " << o[1] << " " << o[2] << ", direction " << v[0] << " "
            << v[1] << " " << v[2] << ")";
      if (!check(expectHit == !segments.empty(), label.str() + ": hit/miss agrees with clipping"))
      {
        continue;
      }
      if (!expectHit)
      {
        continue;
      }
      ++hits;
      CheckStructure(segments, dims, t0, t1, label.str());
      const int samples = 500;
      size_t s = 0;
      for (int k = 0; k < samples; ++k)
      {
        const double t = t0 + (t1 - t0) * (k + 0.5) / samples;
        while (s + 1 < segments.size() && t > segments[s].T1)
        {
          ++s;
        }
        // Points within 1e-9 of a grid plane may belong to either cell: skip them.
        bool ambiguous = false;
        std::array<int, 3> cell;
        for (int a = 0; a < 3; ++a)
        {
          const double p = o[a] + t * v[a];
          ambiguous = ambiguous || std::abs(p - std::round(p)) < 1e-9;
          cell[a] = std::min(std::max(static_cast<int>(std::floor(p)), 0), dims[a] - 2);
        }
        if (!ambiguous && segments[s].Cell != cell)
        {
          ++mismatches;
          if (mismatches < 5)
          {
            std::cerr << label.str() << ": t = " << t << " lies in cell (" << cell[0] << ","
                      << cell[1] << "," << cell[2] << ") but the traversal gives"
                      << Describe({ segments[s] }) << "\n";
          }
        }
      }
    }
    check(hits > 1500, "enough random rays hit the grid (" + std::to_string(hits) + ")");
    check(mismatches == 0,
      "brute-force cell of every sample matches the traversal (" + std::to_string(mismatches) +
        " mismatches)");
  }

  //----------------------------------------------------------------------------
  // Exit points: the coordinates of the planes crossed are exact integers, the others lie on
  // the ray at t1.
  {
    const int dims[3] = { 6, 5, 7 };
    const double o[3] = { -0.7, 0.3, 6.9 }, v[3] = { 0.9, 0.35, -0.8 };
    vtkGridRayTraversal walk;
    walk.Initialize(dims, o, v, -inf, inf);
    int cell[3], previous[3] = { 0, 0, 0 };
    double t0, t1, exit[3];
    bool first = true, ok = true;
    std::array<double, 3> last;
    while (walk.Next(cell, t0, t1))
    {
      if (!first)
      {
        for (int a = 0; a < 3; ++a)
        {
          // The plane between two cells along a crossed axis.
          ok = ok && (cell[a] == previous[a] || last[a] == std::max(cell[a], previous[a]));
        }
      }
      walk.GetExitPoint(exit);
      for (int a = 0; a < 3; ++a)
      {
        ok = ok && std::abs(exit[a] - (o[a] + t1 * v[a])) < 1e-12;
        last[a] = exit[a];
        previous[a] = cell[a];
      }
      first = false;
    }
    check(ok, "exit points lie on the ray and on the crossed planes exactly");
  }

  //----------------------------------------------------------------------------
  // The paper's Figure 3: float traversals of a 256^3 grid, 96 x 96 parallel rays across it.
  // At every plane crossing, the error is the distance (in voxels, evaluated in double) of
  // the crossing's parameter from the plane the walk claims to cross; the paper colours the
  // sum along the ray. Amanatides-Woo adds t_delta to t_max at every step, so its rounding
  // errors add up; the integer traversal recomputes each crossing from integer plane
  // coordinates, so every crossing is one rounding from exact, whatever the step count.
  {
    const int n = 257; // points: 256 cells per axis
    const int dims[3] = { n, n, n };
    const int pixels = 96;
    // Oblique direction, no component a simple ratio of another.
    const double dir[3] = { 0.6123724356957945, 0.5477225575051661, 0.5700877125495690 };
    // Ray origins on a plane in front of the grid, perpendicular to dir.
    const double up[3] = { -0.7071067811865476, 0.7071067811865476, 0.0 };
    double side[3] = { dir[1] * up[2] - dir[2] * up[1],
      dir[2] * up[0] - dir[0] * up[2],
      dir[0] * up[1] - dir[1] * up[0] };
    const double centre[3] = {
      128.0 - 230.0 * dir[0], 128.0 - 230.0 * dir[1], 128.0 - 230.0 * dir[2]
    };
    struct Errors
    {
      double Sum = 0;       // over all crossings of all rays
      double MaxRaySum = 0; // the paper's per-pixel accumulated error, worst pixel
      double MaxEarly = 0;  // worst single crossing among the first 32 of a ray
      double MaxLate = 0;   // worst single crossing after the 512th
      long Crossings = 0;
      long WrongCells = 0;      // segments whose middle lies in another cell
      double ExactPlaneSum = 0; // |exit point - plane| on crossed axes (integer walk only)
    };
    Errors integer, incremental;
    auto record = [](Errors& e, double error, long index, double& raySum)
    {
      e.Sum += error;
      raySum += error;
      ++e.Crossings;
      if (index < 32)
      {
        e.MaxEarly = std::max(e.MaxEarly, error);
      }
      if (index >= 512)
      {
        e.MaxLate = std::max(e.MaxLate, error);
      }
    };
    // A segment's middle must fall in its cell unless it is within 1e-3 of a plane.
    auto wrongCell = [](const double o[3], const double v[3], double t0, double t1, const int c[3])
    {
      const double t = 0.5 * (t0 + t1);
      for (int a = 0; a < 3; ++a)
      {
        const double p = o[a] + t * v[a];
        if (std::abs(p - std::round(p)) < 1e-3)
        {
          return false;
        }
      }
      for (int a = 0; a < 3; ++a)
      {
        if (static_cast<int>(std::floor(o[a] + t * v[a])) != c[a])
        {
          return true;
        }
      }
      return false;
    };
    long rays = 0;
    for (int py = 0; py < pixels; ++py)
    {
      for (int px = 0; px < pixels; ++px)
      {
        const double u = (px + 0.5) / pixels * 2.0 - 1.0, w = (py + 0.5) / pixels * 2.0 - 1.0;
        float of[3], vf[3];
        double o[3], v[3]; // the float ray, exactly, in double
        for (int a = 0; a < 3; ++a)
        {
          of[a] = static_cast<float>(centre[a] + 190.0 * (u * side[a] + w * up[a]));
          // A slight fan so that rays differ in direction too.
          vf[a] = static_cast<float>(dir[a] + 0.05 * (u * side[a] + w * up[a]));
          o[a] = of[a];
          v[a] = vf[a];
        }

        // Integer-based traversal.
        vtkGridRayTraversalT<float> walk;
        if (!walk.Initialize(dims, of, vf, 0.0f, std::numeric_limits<float>::infinity()))
        {
          continue;
        }
        ++rays;
        int cell[3], previous[3];
        float t0, t1, exitPoint[3];
        long index = 0;
        double raySum = 0;
        bool first = true;
        float lastExit[3] = { 0, 0, 0 };
        float lastT = 0;
        while (walk.NextCell(cell, t0, t1))
        {
          if (!first)
          {
            for (int a = 0; a < 3; ++a)
            {
              if (cell[a] != previous[a])
              {
                const int plane = std::max(cell[a], previous[a]);
                record(integer,
                  std::abs(o[a] + static_cast<double>(lastT) * v[a] - plane),
                  index++,
                  raySum);
                integer.ExactPlaneSum += std::abs(lastExit[a] - plane);
              }
            }
          }
          integer.WrongCells += wrongCell(o, v, t0, t1, cell) && t1 - t0 > 1e-3f;
          walk.GetExitPoint(exitPoint);
          std::copy(exitPoint, exitPoint + 3, lastExit);
          std::copy(cell, cell + 3, previous);
          lastT = t1;
          first = false;
        }
        integer.MaxRaySum = std::max(integer.MaxRaySum, raySum);

        // Amanatides-Woo with float state, from the same entry.
        float tmin = 0.0f, tmax = std::numeric_limits<float>::infinity();
        const float lo[3] = { 0, 0, 0 }, hi[3] = { n - 1.0f, n - 1.0f, n - 1.0f };
        vtkGridRayTraversalT<float>::ClipToBox(lo, hi, of, vf, tmin, tmax);
        int c[3], step[3];
        float tMax[3], tDelta[3];
        for (int a = 0; a < 3; ++a)
        {
          const float e = std::min(std::max(of[a] + tmin * vf[a], 0.0f), n - 1.0f);
          step[a] = vf[a] > 0 ? 1 : -1;
          c[a] = std::min(std::max(static_cast<int>(std::floor(e)), 0), n - 2);
          const float plane = static_cast<float>(step[a] > 0 ? c[a] + 1 : c[a]);
          tMax[a] = tmin + (plane - e) / vf[a];
          tDelta[a] = 1.0f / std::abs(vf[a]);
        }
        index = 0;
        raySum = 0;
        float t = tmin;
        while (true)
        {
          const int a =
            tMax[0] < tMax[1] ? (tMax[0] < tMax[2] ? 0 : 2) : (tMax[1] < tMax[2] ? 1 : 2);
          const float tNext = std::min(tMax[a], tmax);
          incremental.WrongCells += wrongCell(o, v, t, tNext, c) && tNext - t > 1e-3f;
          if (tMax[a] >= tmax)
          {
            break;
          }
          const int plane = step[a] > 0 ? c[a] + 1 : c[a];
          record(incremental,
            std::abs(o[a] + static_cast<double>(tMax[a]) * v[a] - plane),
            index++,
            raySum);
          t = tMax[a];
          c[a] += step[a];
          tMax[a] += tDelta[a];
          if (c[a] < 0 || c[a] > n - 2)
          {
            break;
          }
        }
        incremental.MaxRaySum = std::max(incremental.MaxRaySum, raySum);
      }
    }
    auto print = [](const char* name, const Errors& e)
    {
      std::cout << name << ": " << e.Crossings << " crossings, mean error " << e.Sum / e.Crossings
                << " voxel, worst in the first 32 crossings " << e.MaxEarly
                << ", worst after the 512th " << e.MaxLate << ", worst accumulated per ray "
                << e.MaxRaySum << ", wrong cells " << e.WrongCells << "\n";
    };
    std::cout << "Figure 3, " << rays << " float rays through 256^3 cells:\n";
    print("  integer-based", integer);
    print("  Amanatides-Woo", incremental);
    std::cout << "  integer-based exit points off their planes, summed: " << integer.ExactPlaneSum
              << "\n";
    check(rays > pixels * pixels / 2, "most rays hit the grid");
    check(integer.ExactPlaneSum == 0.0,
      "integer traversal: exit points on crossed planes are exact (zero accumulated error)");
    check(integer.WrongCells == 0, "integer traversal: no wrong cells");
    // One rounding of a float t near 450 (ulp 3e-5) times a direction component below 1.
    check(integer.MaxLate <= 1e-4 && integer.MaxEarly <= 1e-4,
      "integer traversal: every crossing within one rounding of its plane");
    check(integer.MaxLate <= 4 * integer.MaxEarly + 1e-5,
      "integer traversal: late crossings no worse than early ones (no accumulation)");
    check(incremental.MaxLate >= 10 * integer.MaxLate,
      "Amanatides-Woo in float accumulates error an order above the integer traversal");
  }

  return check.Result("TestGridRayTraversal");
}
