// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkGridRayTraversal: the cells a ray crosses, in order, with contiguous parameter intervals
// that add up to the chord; special rays (axis-aligned, through edges and corners, on faces,
// from inside, negative directions, misses, one-cell grids) and random rays against brute
// force sampling.
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

// Segments of positive length only.
std::vector<Segment> NonEmpty(const std::vector<Segment>& all)
{
  std::vector<Segment> out;
  std::copy_if(
    all.begin(), all.end(), std::back_inserter(out), [](const Segment& s) { return s.T1 > s.T0; });
  return out;
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
// non-decreasing, end at the exit, and consecutive cells are face neighbours inside the grid.
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
    check(s.T1 >= s.T0, label + ": non-negative interval," + Describe({ s }));
    if (n > 0)
    {
      // Contiguous: each interval starts exactly where the previous one ended.
      check(s.T0 == segments[n - 1].T1,
        label + ": contiguous intervals," + Describe({ segments[n - 1], s }));
      int moved = 0;
      for (int a = 0; a < 3; ++a)
      {
        moved += std::abs(s.Cell[a] - segments[n - 1].Cell[a]);
      }
      check(moved == 1,
        label + ": consecutive cells are face neighbours," + Describe({ segments[n - 1], s }));
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
  // Through corners and edges: ties step one axis at a time with zero-length segments; the
  // cells of positive length are the diagonal ones.
  {
    const int dims[3] = { 4, 4, 4 };
    const double o[3] = { -1.0, -1.0, -1.0 }, v[3] = { 1.0, 1.0, 1.0 };
    const auto all = Traverse(dims, o, v);
    CheckStructure(all, dims, 1.0, 4.0, "main diagonal");
    CheckExact(NonEmpty(all),
      { { { 0, 0, 0 }, 1, 2 }, { { 1, 1, 1 }, 2, 3 }, { { 2, 2, 2 }, 3, 4 } },
      "main diagonal, cells of positive length");
    const double on[3] = { 4.0, 4.0, 4.0 }, vn[3] = { -1.0, -1.0, -1.0 };
    CheckExact(NonEmpty(Traverse(dims, on, vn)),
      { { { 2, 2, 2 }, 1, 2 }, { { 1, 1, 1 }, 2, 3 }, { { 0, 0, 0 }, 3, 4 } },
      "reversed main diagonal, cells of positive length");
    // Along an edge line x = y in the plane z = 1.5: crosses the edges x = y = 1, 2.
    const double oe[3] = { 0.0, 0.0, 1.5 }, ve[3] = { 1.0, 1.0, 0.0 };
    const auto edge = Traverse(dims, oe, ve);
    CheckStructure(edge, dims, 0.0, 3.0, "x = y diagonal");
    CheckExact(NonEmpty(edge),
      { { { 0, 0, 1 }, 0, 1 }, { { 1, 1, 1 }, 1, 2 }, { { 2, 2, 1 }, 2, 3 } },
      "x = y diagonal, cells of positive length");
    // Anti-diagonal in x, y through the edges x + y = 3.
    const double oa[3] = { 0.0, 3.0, 0.25 }, va[3] = { 1.0, -1.0, 0.0 };
    const auto anti = Traverse(dims, oa, va);
    CheckStructure(anti, dims, 0.0, 3.0, "anti-diagonal");
    CheckExact(NonEmpty(anti),
      { { { 0, 2, 0 }, 0, 1 }, { { 1, 1, 0 }, 1, 2 }, { { 2, 0, 0 }, 2, 3 } },
      "anti-diagonal, cells of positive length");
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
      { { { 0, 1, 2 }, -1, -0.5 },
        { { 1, 1, 2 }, -0.5, -0.5 },
        { { 1, 1, 1 }, -0.5, 0.5 },
        { { 2, 1, 1 }, 0.5, 0.75 } },
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

  return check.Result("TestGridRayTraversal");
}
