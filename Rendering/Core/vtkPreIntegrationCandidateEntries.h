// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkPreIntegrationCandidateEntries
 * @brief   the entries of candidate tables that rays read, integrated once and shared
 *
 * vtkPreIntegrationTableSizer measures candidate tables by compositing rays' pieces through
 * them, and a ray reads few of a large candidate's entries. This store holds the entries of
 * one grid (centre size, chord and deviation axes) of a vtkSecondOrderPreIntegrationTable's
 * settings, each integrated when a ray first reads it by the builders' own kernel
 * (vtkSecondOrderPreIntegrationTableKernel, so that it equals the built table's), safely from
 * several threads. A candidate of the same centre size and prefilter whose chord and
 * deviation entries fall on the store's grid (spacings that are multiples of the store's,
 * within its extents) reads through a Lookup that maps its entries onto the store's: the
 * candidates of one centre size, whose spacings are 1, 2, 4 or 8 times the centre spacing,
 * share one store and integrate each entry they have in common once.
 *
 * The values are left uninitialized and the states come from calloc (zero pages mapped on
 * first touch), so that neither costs time in proportion to the grid's size. A store outlives
 * an edit of the transfer functions: Update() takes the new ones and forgets only the entries
 * whose paths read an iteration-table sample that changed (the others keep their values, bit
 * for bit, as vtkSecondOrderPreIntegrationTable's incremental build does).
 *
 * Part of vtkPreIntegrationTableSizer: a value class for its inner loops (not a vtkObject,
 * not wrapped, not installed).
 */
#ifndef vtkPreIntegrationCandidateEntries_h
#define vtkPreIntegrationCandidateEntries_h

#include "vtkNew.h"                                  // For the grid's table
#include "vtkPreIntegrationRayMarch.h"               // For TableView
#include "vtkSecondOrderPreIntegrationTableKernel.h" // For the kernel
#include "vtkType.h"                                 // For vtkIdType

#include <atomic>  // For the entry states
#include <cstdlib> // For std::free
#include <memory>  // For std::unique_ptr
#include <vector>  // For the kernel's scratch

class vtkSecondOrderPreIntegrationTable;

class vtkPreIntegrationCandidateEntries
{
public:
  vtkPreIntegrationCandidateEntries();
  ~vtkPreIntegrationCandidateEntries();

  /**
   * Make the store for the grid of a table of `settings`' transfer functions, scalar range,
   * segment length and iterations, with this prefilter and these sizes and ranges (chord and
   * deviation axes symmetric about 0, as vtkSecondOrderPreIntegrationTable's). No entry is
   * integrated yet. False when the transfer functions cannot be sampled or memory runs out.
   */
  bool Allocate(vtkSecondOrderPreIntegrationTable* settings,
    bool prefilter,
    int tableSize,
    int chordSize,
    double chordRange,
    int deviationSize,
    double deviationRange);

  /**
   * Take the transfer functions of `settings` for the same grid as the last Allocate() (the
   * same arguments, and the same scalar range, segment length and iterations of `settings`):
   * the entries whose paths read an iteration-table sample that changed are integrated
   * again when next read, the others stay. False, with the store unchanged, when the grid
   * or the kernel differ (a new transfer function can change the iteration table's
   * resolution): Allocate() then makes a new store.
   */
  bool Update(vtkSecondOrderPreIntegrationTable* settings,
    bool prefilter,
    int tableSize,
    int chordSize,
    double chordRange,
    int deviationSize,
    double deviationRange);

  /**
   * Bytes the store reserves (values and states; only the pages of entries read are touched).
   */
  double GetReservedBytes() const;

  /**
   * The store's axis a (1: chord, 2: deviation): its entries and its spacing in data units
   * (0 for a single entry).
   */
  int GetSize(int a) const { return this->Size[a]; }
  double GetSpacing(int a) const { return this->Spacing[a]; }

  /**
   * Whether every entry whose path stays within scalars [low, high] (data units) lies inside
   * one zero-opacity run of the store's iteration table, so that it is exactly zero (the
   * kernel's empty path). The range is widened by a sample on each side against rounding.
   */
  bool IsEmptyBetween(double low, double high) const;

  /**
   * Reads a candidate's table through the store: axis a of the candidate has Size[a] entries
   * at values Low[a] + i / ToIndex[a] (its own view), and its entry i is the store's entry
   * Offset[a] + Scale[a] i. Read() composes as March::TablePieces does, so that it can stand
   * for a table in vtkPreIntegrationTableSizer's compositing.
   */
  struct Lookup
  {
    vtkPreIntegrationRayMarch::TableView View; // the candidate's axes
    int Offset[3] = { 0, 0, 0 };
    int Scale[3] = { 1, 1, 1 };
    const vtkPreIntegrationCandidateEntries* Store = nullptr;
    // The kernel's scratch: each chunk of rays copies the lookup, so that an entry costs no
    // allocation.
    mutable std::vector<float> Steps;

    void Read(const double v[3], double fraction, double rgba[4]) const;
  };

  /**
   * The lookup of a candidate of tableSize x chordSize x deviationSize entries over these
   * ranges through this store; false when its entries do not fall on the store's grid.
   */
  bool MakeLookup(int tableSize,
    int chordSize,
    double chordRange,
    int deviationSize,
    double deviationRange,
    Lookup& lookup) const;

private:
  // Store entry `index` is integrated (once, by whichever thread reads it first).
  void Ensure(vtkIdType index, std::vector<float>& steps) const;

  vtkNew<vtkSecondOrderPreIntegrationTable> Table; // the grid's iteration table and kernel
  vtkSecondOrderPreIntegrationTableKernel Kernel;
  const float* Samples = nullptr;
  const float* Runs = nullptr;
  double Range[2] = { 0, 1 }; // scalar range
  int Size[3] = { 1, 1, 1 };
  double Spacing[3] = { 0, 0, 0 };
  double Low[3] = { 0, 0, 0 };
  std::unique_ptr<float[]> Values;
  std::unique_ptr<std::atomic<unsigned char>, decltype(&std::free)> States;

  vtkPreIntegrationCandidateEntries(const vtkPreIntegrationCandidateEntries&) = delete;
  void operator=(const vtkPreIntegrationCandidateEntries&) = delete;
};

#endif
