"""Measured table sizes hold on transfer functions and data nobody tuned them for.

Random cases (seeded, generated here): a volume (smooth blobs, sums of plane waves or
Marschner-Lobb, 26 to 36 points a side) stored as uint8, 16-bit (12- or 16-bit range) or float
(a random range from 0.01 to 10^4 wide), a transfer function of one to four random features
(opacity spikes, steps to a plateau, plateaus with steep sides, ramps; widths 0.2% to 15% of
the range, peak opacities 0.02 to 1), a random unit distance and a step of 1/4 to 4 voxels.
For each case and both orders, vtkPreIntegrationTableSizer chooses the table's sizes (and for
first order, as the mapper's automatic prefilter does, whether to prefilter); an independent
judge (another sizer: other seed, four times the rays) then measures, on its own rays, the
error of the chosen table and of every table of a sweep (centre axes of 33 to 2049 entries,
chord and deviation spacings 1, 2, 4 and 8 times the centre spacing, within the memory limit;
for first order each with and without the prefilter), all with the chosen chord and deviation
ranges. The chosen table must come within 5% of
the best of the sweep, to the precision the judge's rays measure it: the per-ray errors are
heavy-tailed (rays grazing a sharp feature carry most of the error), so independent ray sets of
8192 rays can disagree on a table's error by 10%. A case fails when the judge finds the chosen
table more than 5% worse with confidence: its mean squared error minus two standard errors of
the per-ray differences to the best exceeds 1.05^2 times the best's. The cases are printed with
both the measured ratio and that confidence bound; the worst case, and the build time and
memory of the chosen tables, are printed too. An argument K/N runs the cases whose number is K-1
modulo N (ctest runs the halves in parallel); --cases M runs the first M cases (default 50;
ctest runs 12 to keep the test suite short, the whole 50 is run by hand, as docs/performance.md
says).

The judge measures on rays, not on a camera image, to see many directions at once; the rays
are composited as the shader does (vtkPreIntegrationRayMarch, which matches the GPU image,
TestPreIntegrationRayCaster) with the builders' own entries (the kernel,
TestSecondOrderPreIntegrationTable). Each case is also chosen without the screening
(vtkPreIntegrationTableSizer::ScreeningFraction 1, every candidate measured on all the rays)
from the same table state: the judge must find the screened choice's error within 2% of that
choice's, with the same confidence rule. In the first four cases every candidate measured on all
the rays (not dropped by the screening) must measure, bit for bit, as the candidate measured
alone: with the entries its centre size shares, with those kept from the Choose() before an edit
of the opacity, and under small axis and memory limits; and after a random edit of a colour node
and of an opacity node, the sizer, which keeps its reference's cells and its exact model's pieces
where the edit does not reach, must measure every candidate and the exact model as a fresh sizer
does, bit for bit.
"""

import math
import sys
import time

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkDoubleArray

import hovr
from hovr import randomcases
from hovrtesting import Checker

CASES = 50          # random transfer functions, each for both orders
FIRST_SEED = 1000   # clear of seeds 0-59, the sizer's tuning cases
JUDGE_RAYS = 8192
TOLERANCE = 1.05    # the chosen table's error over the best swept table's
SCREENED_TOLERANCE = 1.02  # the chosen table's error over the unscreened choice's


def sweep_axis(extent, spacing):
    return max(3, 2 * math.ceil(extent / spacing - 1e-9) + 1)


def run_case(seed, order, step, image, prop, table, sizer, judge):
    """The sizer's choice for one order and the judge's sweep. The table, the sizer and the
    judge serve both orders of a case: the sizers keep their rays' reference between them."""
    scalars = image.GetPointData().GetScalars()
    low, high = scalars.GetRange()
    table.SetVolumeProperty(prop)
    table.SetScalarRange(low, high)
    table.SetSegmentLength(order * step)
    table.SetPrefilter(False)
    sizer.SetMeasurePrefilter(order == 1)  # as the mapper's automatic prefilter
    before = table_state(table)
    start = time.perf_counter()
    if not sizer.Choose(image, scalars, table, order, step):
        return None
    choose_s = time.perf_counter() - start
    chosen = (table.GetTableSize(), table.GetChordSize(), table.GetDeviationSize())
    chosen_prefilter = table.GetPrefilter()
    chord, deviation = table.GetChordRange(), table.GetDeviationRange()
    after = table_state(table)
    # The same choice without the screening (every candidate on all the rays), from the same
    # table state.
    full = hovr.vtkPreIntegrationTableSizer()
    full.SetMeasurePrefilter(order == 1)
    full.SetScreeningFraction(1.0)
    set_table_state(table, before)
    full.Choose(image, scalars, table, order, step)
    unscreened = table_state(table)
    set_table_state(table, unscreened)
    judge.Prepare(image, scalars, table, order, step)
    unscreened_error = judge.Measure(*unscreened[:3], unscreened[3], unscreened[4])
    unscreened_rays = vtkDoubleArray()
    judge.GetLastMeasurePerRay(unscreened_rays)
    set_table_state(table, after)
    chosen_error = judge.Measure(*chosen, chord, deviation)
    chosen_rays = vtkDoubleArray()
    judge.GetLastMeasurePerRay(chosen_rays)
    differences = vtk_to_numpy(chosen_rays) - vtk_to_numpy(unscreened_rays)
    margin = 2.0 * differences.std() / math.sqrt(differences.size)
    screened_lower = (math.sqrt(max(unscreened_error ** 2, chosen_error ** 2 - margin)) /
                      unscreened_error if unscreened_error > 0 else 1.0)
    screened_ratio = chosen_error / unscreened_error if unscreened_error > 0 else 1.0
    best_error, best, best_rays = math.inf, None, None
    best_by_prefilter = {}
    width = high - low
    limit = sizer.GetMaximumMemory()
    for prefilter in ((False, True) if order == 1 else (False,)):
        table.SetPrefilter(prefilter)  # what the judge's Measure() uses
        for level in range(5, 12):
            centre = 2 ** level + 1
            spacing = width / (centre - 1)
            for fb in (1, 2, 4, 8):
                for fd in ((1, 2, 4, 8) if order == 2 else (1,)):
                    sizes = (centre, sweep_axis(chord, fb * spacing),
                             sweep_axis(deviation, fd * spacing) if order == 2 else 1)
                    if max(sizes) > 4097 or sizes[0] * sizes[1] * sizes[2] * 8 > limit:
                        continue
                    error = judge.Measure(*sizes, chord, deviation)
                    if 0 <= error < best_by_prefilter.get(prefilter, math.inf):
                        best_by_prefilter[prefilter] = error
                    if 0 <= error < best_error:
                        best_error, best = error, sizes + (("prefiltered",) if prefilter else ())
                        best_rays = vtkDoubleArray()
                        judge.GetLastMeasurePerRay(best_rays)
    table.SetPrefilter(chosen_prefilter)
    # Paired over the judge's rays: the chosen table's excess over the best, less two standard
    # errors, as a ratio of errors (1 when they cannot be told apart).
    differences = vtk_to_numpy(chosen_rays) - vtk_to_numpy(best_rays)
    margin = 2.0 * differences.std() / math.sqrt(differences.size)
    lower = math.sqrt(max(best_error ** 2, chosen_error ** 2 - margin)) / best_error
    # The chosen table, built as the mapper builds it.
    start = time.perf_counter()
    table.Update()
    build_s = time.perf_counter() - start
    if chosen_prefilter:
        chosen = chosen + ("prefiltered",)
    return {"chosen": chosen, "chosen_error": chosen_error, "best": best,
            "best_error": best_error, "ratio": chosen_error / best_error if best_error > 0 else 1.0,
            "lower": lower, "prefilter_gain": best_by_prefilter.get(True, math.nan)
            / best_by_prefilter[False], "prefiltered": chosen_prefilter,
            "choose_s": choose_s, "build_s": build_s, "screened_ratio": screened_ratio,
            "screened_lower": screened_lower, "same_as_unscreened": after == unscreened,
            "mib": table.GetNumberOfEntries() * 8 / 2 ** 20}


def table_state(table):
    return (table.GetTableSize(), table.GetChordSize(), table.GetDeviationSize(),
            table.GetChordRange(), table.GetDeviationRange(), table.GetPrefilter())


def set_table_state(table, state):
    table.SetTableSize(state[0])
    table.SetChordSize(state[1])
    table.SetDeviationSize(state[2])
    table.SetChordRange(state[3])
    table.SetDeviationRange(state[4])
    table.SetPrefilter(state[5])


def alone_mismatches(sizer, table):
    """Candidates of the last Choose() whose error, measured with the entries their centre size
    shares, differs from Measure() of the candidate alone (its own entries): none may, bit for
    bit, as shared entries are the same integrals."""
    kept = table.GetPrefilter()
    sizes, ranges, wrong = [0, 0, 0], [0.0, 0.0], []
    for i in range(sizer.GetNumberOfCandidates()):
        if sizer.GetCandidateDropped(i):
            continue  # its error is over the screening rays alone
        sizer.GetCandidateSizes(i, sizes)
        sizer.GetCandidateRanges(i, ranges)
        table.SetPrefilter(sizer.GetCandidatePrefilter(i))
        alone = sizer.Measure(*sizes, *ranges)
        if alone != sizer.GetCandidateError(i):
            wrong.append((tuple(sizes), sizer.GetCandidateError(i), alone))
    table.SetPrefilter(kept)
    return wrong


def edit_mismatch(sizer, table, image, order, step, function, edit):
    """Edit one node of function (its values per edit(node, rng)), Choose() with sizer (which
    kept its reference's cells and the exact model's pieces) and with a fresh sizer from the
    same table state, and restore the node: None when both measure every candidate and the
    exact model alike (the kept values are the same integrals), else what differs."""
    scalars = image.GetPointData().GetScalars()
    size = 6 if function.IsA("vtkColorTransferFunction") else 4
    node = [0.0] * size
    index = int(edit.rng.integers(function.GetSize()))
    function.GetNodeValue(index, node)
    function.SetNodeValue(index, edit(list(node)))
    state = table_state(table)
    measured = []
    try:
        sizer.SetMeasureExactModel(True)
        fresh = hovr.vtkPreIntegrationTableSizer()
        fresh.CopySettings(sizer)
        for one in (sizer, fresh):
            set_table_state(table, state)
            if not one.Choose(image, scalars, table, order, step):
                return "a Choose() failed"
            sizes = [0, 0, 0]
            candidates = []
            for i in range(one.GetNumberOfCandidates()):
                one.GetCandidateSizes(i, sizes)
                candidates.append((tuple(sizes), one.GetCandidateError(i)))
            measured.append((candidates, one.GetExactError(), table_state(table)))
    finally:
        sizer.SetMeasureExactModel(False)
        function.SetNodeValue(index, node)
        set_table_state(table, state)
    (kept, kept_exact, kept_state), (new, new_exact, new_state) = measured
    if kept_state != new_state or [k[0] for k in kept] != [n[0] for n in new]:
        return "chosen %s and %s, candidates %d and %d" % (kept_state, new_state, len(kept),
                                                            len(new))
    for (sizes, a), (_, b) in zip(kept, new):
        if a != b:
            return "candidate %s: %.17g and %.17g" % (sizes, a, b)
    return None if kept_exact == new_exact else "exact %.17g and %.17g" % (kept_exact, new_exact)


class NodeEdit:
    """A random edit of a node's values: its colour (colour nodes) or its opacity."""

    def __init__(self, rng, colour):
        self.rng = rng
        self.colour = colour

    def __call__(self, node):
        if self.colour:
            node[1:4] = [float(v) for v in self.rng.uniform(0.0, 1.0, 3)]
        else:
            node[1] = float(self.rng.uniform(0.0, 1.0))
        return node


arguments = sys.argv[1:]
if "--cases" in arguments:
    at = arguments.index("--cases")
    CASES = int(arguments[at + 1])
    del arguments[at:at + 2]
PART, PARTS = (int(k) for k in arguments[0].split("/")) if arguments else (1, 1)
CASE_NUMBERS = [k for k in range(CASES) if k % PARTS == PART - 1]

c = Checker()
results = []
for case in CASE_NUMBERS:
    seed = FIRST_SEED + case
    rng = numpy.random.default_rng(seed)
    image, volume_name = randomcases.volume(rng)
    low, high = image.GetPointData().GetScalars().GetRange()
    prop, tf_name = randomcases.transfer_function(
        rng, low, high, features=(1, 5), kinds=("spike", "step", "plateau", "ramp"),
        widths=(0.002, 0.15), centres=(0.05, 0.95), log_heights=(-1.7, 0.0),
        colour_points=(2, 6), log_units=(math.log10(0.3), math.log10(5)))
    step = float(rng.choice([0.25, 0.5, 1.0, 2.0, 4.0]))
    table = hovr.vtkSecondOrderPreIntegrationTable()
    sizer = hovr.vtkPreIntegrationTableSizer()
    sizer.SetKeepEntries(True)  # the edit check below measures with the kept entries
    judge = hovr.vtkPreIntegrationTableSizer()
    judge.SetSeed(10000 + seed)
    judge.SetNumberOfRays(JUDGE_RAYS)
    for order in (1, 2):
        result = run_case(seed, order, step, image, prop, table, sizer, judge)
        if not c.check(result is not None, "seed %d order %d: the sizer chooses" % (seed, order)):
            continue
        if order == 2 and case < 5:
            # The sizer kept its reference from order 1: a fresh one must choose the same.
            fresh_table = hovr.vtkSecondOrderPreIntegrationTable()
            fresh_table.SetVolumeProperty(prop)
            fresh_table.SetScalarRange(*image.GetPointData().GetScalars().GetRange())
            fresh_table.SetSegmentLength(order * step)
            hovr.vtkPreIntegrationTableSizer().Choose(image, image.GetPointData().GetScalars(),
                                                      fresh_table, order, step)
            fresh = (fresh_table.GetTableSize(), fresh_table.GetChordSize(),
                     fresh_table.GetDeviationSize())
            c.check(fresh == result["chosen"], "seed %d: a fresh sizer chooses %s as the one "
                    "that kept its reference (%s)" % (seed, fresh, result["chosen"]))
        if case < 4:
            wrong = alone_mismatches(sizer, table)
            c.check(not wrong, "seed %d order %d: %d candidates measure as alone (%s)" % (
                seed, order, sizer.GetNumberOfCandidates(), wrong[:3]))
            # An edit of the highest opacity node: the sizer's entries kept from the last
            # Choose() take the new transfer function, and every candidate still measures as
            # alone (entries integrated afresh).
            opacity = prop.GetScalarOpacity()
            nodes = [[0.0] * 4 for _ in range(opacity.GetSize())]
            for i, node in enumerate(nodes):
                opacity.GetNodeValue(i, node)
            peak = max(range(len(nodes)), key=lambda i: nodes[i][1])
            edited = list(nodes[peak])
            edited[1] *= 0.8
            opacity.SetNodeValue(peak, edited)
            if c.check(sizer.Choose(image, image.GetPointData().GetScalars(), table, order, step),
                       "seed %d order %d: the sizer chooses after an edit" % (seed, order)):
                wrong = alone_mismatches(sizer, table)
                c.check(not wrong, "seed %d order %d: after an edit, %d candidates measure with "
                        "the kept entries as alone (%s)" % (
                            seed, order, sizer.GetNumberOfCandidates(), wrong[:3]))
            opacity.SetNodeValue(peak, nodes[peak])
            # An edit of one colour node's colour, then of one opacity node's opacity: the
            # sizer integrates again only the reference's cells and the exact model's pieces
            # the edit reaches (none of the cells for colours kept as node weights); a fresh
            # sizer (from the same table state) must measure every candidate and the exact
            # model alike, bit for bit.
            for function, colour in ((prop.GetRGBTransferFunction(), True),
                                     (prop.GetScalarOpacity(), False)):
                mismatch = edit_mismatch(sizer, table, image, order, step, function,
                                         NodeEdit(rng, colour))
                c.check(mismatch is None, "seed %d order %d: after an edit of a %s node, the "
                        "kept and a fresh sizer measure alike, bit for bit (%s)" % (
                            seed, order, "colour" if colour else "opacity", mismatch))
            # Axes cut to a size limit and a small memory limit: candidates off the shared grid
            # and levels without one.
            small = hovr.vtkPreIntegrationTableSizer()
            small.SetMaximumAxisSize(45)
            small.SetMaximumMemory(256 * 1024)
            small.SetMeasurePrefilter(order == 1)
            if c.check(small.Choose(image, image.GetPointData().GetScalars(), table, order, step),
                       "seed %d order %d: the sizer chooses under small limits" % (seed, order)):
                wrong = alone_mismatches(small, table)
                c.check(not wrong, "seed %d order %d: %d candidates under small limits measure "
                        "as alone (%s)" % (seed, order, small.GetNumberOfCandidates(), wrong[:3]))
        result["label"] = "seed %d, order %d, step %g, %s, %s, unit %.2f" % (
            seed, order, step, volume_name, tf_name, prop.GetScalarOpacityUnitDistance())
        results.append(result)
        print("%s: chosen %s (%.2f MiB, measured in %.2f s, built in %.3f s) error %.3e; best "
              "%s error %.3e; ratio %.3f (at least %.3f with confidence)" % (
                  result["label"], "x".join(map(str, result["chosen"])), result["mib"],
                  result["choose_s"], result["build_s"], result["chosen_error"],
                  "x".join(map(str, result["best"])), result["best_error"], result["ratio"],
                  result["lower"]))
        sys.stdout.flush()

ratios = numpy.array([r["ratio"] for r in results])
lowers = numpy.array([r["lower"] for r in results])
worst = max(results, key=lambda r: r["ratio"])
print("%d cases: chosen error over the best swept: median %.3f, worst %.3f (at least %.3f with "
      "confidence; %s); %d over %.2f as measured, %d with confidence"
      % (len(results), numpy.median(ratios), worst["ratio"], worst["lower"], worst["label"],
         int((ratios > TOLERANCE).sum()), TOLERANCE, int((lowers > TOLERANCE).sum())))
fresh = [r["choose_s"] for r in results if r["label"].split(", ")[1] == "order 1"]
kept = [r["choose_s"] for r in results if r["label"].split(", ")[1] == "order 2"]
print("chosen tables: memory median %.2f MiB, largest %.2f MiB; building median %.3f s, longest "
      "%.3f s; measuring, first order with its rays' reference (as for a new transfer function), "
      "median %.2f s, longest %.2f s; second order, the reference kept (as when the step or the "
      "order changes), median %.2f s, longest %.2f s" % (
          numpy.median([r["mib"] for r in results]), max(r["mib"] for r in results),
          numpy.median([r["build_s"] for r in results]), max(r["build_s"] for r in results),
          numpy.median(fresh), max(fresh), numpy.median(kept), max(kept)))
screened = numpy.array([r["screened_ratio"] for r in results])
screened_worst = max(results, key=lambda r: r["screened_ratio"])
print("screening: the same sizes as without it in %d of %d; chosen error over the unscreened "
      "choice's (judge's rays): median %.4f, best %.4f, worst %.4f (at least %.4f with "
      "confidence; %s)" % (sum(r["same_as_unscreened"] for r in results), len(results),
                           numpy.median(screened), screened.min(), screened_worst["screened_ratio"],
                           screened_worst["screened_lower"], screened_worst["label"]))
first = [r for r in results if r["label"].split(", ")[1] == "order 1"]
gains = numpy.array([r["prefilter_gain"] for r in first])
print("first order: the best prefiltered table's error over the best unprefiltered one's: median "
      "%.3f, least %.3f, largest %.3f; below 0.95 in %d of %d cases, above 1.05 in %d; the sizer "
      "chose the prefilter in %d" % (numpy.median(gains), gains.min(), gains.max(),
                                     int((gains < 0.95).sum()), len(first),
                                     int((gains > 1.05).sum()),
                                     sum(r["prefiltered"] for r in first)))
c.check(len(results) == 2 * len(CASE_NUMBERS), "every case measured")
for r in results:
    c.check(r["screened_lower"] <= SCREENED_TOLERANCE, "%s: the screened choice's error is within "
            "2%% of the unscreened choice's (%.4f as measured, at least %.4f with confidence)"
            % (r["label"], r["screened_ratio"], r["screened_lower"]))
    c.check(r["lower"] <= TOLERANCE, "%s: the chosen table's error is within 5%% of the best "
            "swept table's (%.3f as measured, at least %.3f with confidence)"
            % (r["label"], r["ratio"], r["lower"]))
c.finish()
