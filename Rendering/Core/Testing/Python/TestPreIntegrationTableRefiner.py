"""vtkPreIntegrationTableRefiner and vtkPreIntegrationTableSizing, without OpenGL.

On a Marschner-Lobb volume (40^3, generated here) with a spike transfer function, both
orders:
- a request measured and built in the worker gives a table the same sizes as
  vtkPreIntegrationTableSizer::Choose in the calling thread, and entries equal (exactly) to
  that table built by Update(); the receiving table counts as built (AdoptBuild: BuildCount up
  by one, a later Update() builds nothing);
- a receiving table whose settings differ (Iterations) takes the sizes but not the entries,
  and builds them itself, the same values again;
- held requests (Paused) are not started; of 10 requests only the newest is measured, the 9
  others count as stopped; Cancel() drops the newest, and nothing is ready after it;
- a request the sizer cannot serve (a transfer function without nodes) fails with a message
  (GetFailure) instead of printing from the worker thread;
- vtkPreIntegrationTableSizing with RefineInBackground: the first Update() answers with an
  interim table of at most InterimEntries entries, a later Update() with the same key takes
  the measured one; the same key again changes nothing; without it, Update() measures at once;
- new data alone (time steps): a step whose values stay in the measured range with a close
  distribution keeps the sizes and the range; values a little beyond it extend the range by
  whole centre spacings; values far outside it, or a distribution far from it, are measured
  again;
- a provisional request (a table of measured sizes, edited): its provisional result is a
  table of those sizes built for the edit (entries equal to that table built here), given
  before the measurement ends, then the measured one; when the measurement finds the same
  sizes, the final result is a confirmation (IsConfirmation) that changes nothing; without
  taking the provisional one, only the measured one waits; the result is the same table either way as a plain request's;
- a provisional request whose table holds a complete build at the kept sizes takes its entries,
  and its provisional table integrates only those the edit reaches (equal to a fresh build),
  also when the request is held and superseded by a second edit before it starts;
- vtkSecondOrderPreIntegrationTable::GetNumberOfEntriesToBuild predicts the entries the next
  build integrates (all at first, fewer after an opacity edit, none when nothing changed);
- deleting a refiner in the middle of a measurement returns (the worker stops at its next
  check).
"""

import math

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkVolumeProperty

import hovr
from hovrtesting import Checker

c = Checker()
source = hovr.vtkMarschnerLobbSource()
source.SetDimensions(40, 40, 40)
source.Update()
image = source.GetOutput()
scalars = image.GetPointData().GetScalars()
low, high = scalars.GetRange()
step = image.GetSpacing()[0]


def make_property(peak=0.6):
    opacity = vtkPiecewiseFunction()
    for x, a in ((0.0, 0.0), (0.47, 0.0), (0.5, peak), (0.53, 0.0), (1.0, 0.0)):
        opacity.AddPoint(low + x * (high - low), a)
    color = vtkColorTransferFunction()
    color.AddRGBPoint(low, 0.1, 0.3, 1.0)
    color.AddRGBPoint(high, 1.0, 0.6, 0.1)
    prop = vtkVolumeProperty()
    prop.SetScalarOpacity(opacity)
    prop.SetColor(color)
    prop.SetScalarOpacityUnitDistance(0.1)
    return prop


def make_table(prop, order, iterations=64):
    table = hovr.vtkSecondOrderPreIntegrationTable()
    table.SetVolumeProperty(prop)
    table.SetScalarRange(low, high)
    table.SetSegmentLength(order * step)
    table.SetIterations(iterations)
    return table


def sizes(table):
    return (table.GetTableSize(), table.GetChordSize(), table.GetDeviationSize())


def entries(table):
    return vtk_to_numpy(table.GetTable()).copy()


prop = make_property()
for order in (1, 2):
    name = "order %d" % order
    # In the calling thread: the sizes and the entries to compare with.
    expected = make_table(prop, order)
    hovr.vtkPreIntegrationTableSizer().Choose(image, scalars, expected, order, step)
    expected.Update()

    refiner = hovr.vtkPreIntegrationTableRefiner()
    request = refiner.Request(image, scalars, make_table(prop, order), order, step, 4097, True)
    refiner.Wait()
    c.check(refiner.IsReady(request), "%s: the request's result waits" % name)
    table = make_table(prop, order)
    c.check(refiner.TakeResult(request, table), "%s: the result is taken" % name)
    c.check(sizes(table) == sizes(expected), "%s: the worker's sizes %s are the calling "
            "thread's %s" % (name, sizes(table), sizes(expected)))
    c.check(table.GetBuildCount() == 1, "%s: the table counts as built" % name)
    adopted = entries(table)
    c.check(table.Update() and table.GetBuildCount() == 1,
            "%s: Update() after the result builds nothing" % name)
    c.check(adopted.shape == entries(expected).shape and
            numpy.array_equal(adopted, entries(expected)),
            "%s: the worker's entries equal the table built here" % name)
    c.check(not refiner.IsReady(request), "%s: a result is taken once" % name)

    # Other settings: the sizes are taken, the entries built by the table itself.
    request = refiner.Request(image, scalars, make_table(prop, order), order, step, 4097, True)
    refiner.Wait()
    other = make_table(prop, order, iterations=32)
    c.check(refiner.TakeResult(request, other) and other.GetBuildCount() == 0,
            "%s: a table of other settings takes the sizes only" % name)
    c.check(other.Update() and sizes(other) == sizes(expected),
            "%s: and builds its own entries" % name)

    # Held, superseded, cancelled.
    refiner.SetPaused(True)
    before = (refiner.GetNumberOfCompleted(), refiner.GetNumberOfStopped())
    requests = [refiner.Request(image, scalars, make_table(make_property(0.1 + 0.05 * k), order),
                                order, step, 4097, True) for k in range(10)]
    refiner.Wait()
    c.check(not refiner.IsReady(requests[-1]) and refiner.IsBusy(),
            "%s: held requests are not started" % name)
    refiner.SetPaused(False)
    refiner.Wait()
    c.check(refiner.IsReady(requests[-1]) and not any(refiner.IsReady(r) for r in requests[:-1]),
            "%s: only the newest of 10 requests is measured" % name)
    c.check(refiner.GetNumberOfCompleted() - before[0] == 1 and
            refiner.GetNumberOfStopped() - before[1] == 9,
            "%s: 1 completed, 9 stopped (%d, %d)" % (
                name, refiner.GetNumberOfCompleted() - before[0],
                refiner.GetNumberOfStopped() - before[1]))
    request = refiner.Request(image, scalars, make_table(prop, order), order, step, 4097, True)
    refiner.Cancel()
    refiner.Wait()
    c.check(not refiner.IsReady(request) and not refiner.IsBusy(),
            "%s: a cancelled request leaves nothing" % name)

    # A request the sizer cannot serve.
    empty = vtkVolumeProperty()
    empty.SetScalarOpacity(vtkPiecewiseFunction())
    empty.SetColor(prop.GetRGBTransferFunction())
    request = refiner.Request(image, scalars, make_table(empty, order), order, step, 4097, True)
    refiner.Wait()
    failure = refiner.GetFailure(request)
    c.check(refiner.Failed(request) and "opacity" in failure,
            "%s: a failed request says why (%r)" % (name, failure))

    # The sizing policy.
    sizing = hovr.vtkPreIntegrationTableSizing()
    sizing.SetRefineInBackground(True)
    key = [1.0, float(order)]
    table = make_table(prop, order)
    data = [1.0]
    c.check(sizing.Update(key, data, image, scalars, table, order, step, 4097, True),
            "%s: the first update answers" % name)
    c.check(sizing.IsRefining() and table.GetNumberOfEntries() <= sizing.GetInterimEntries(),
            "%s: with an interim table of at most %d entries (%d)" % (
                name, sizing.GetInterimEntries(), table.GetNumberOfEntries()))
    sizing.WaitForRefinement()
    c.check(sizing.IsRefinementReady(), "%s: the measured table waits" % name)
    sizing.Update(key, data, image, scalars, table, order, step, 4097, True)
    c.check(not sizing.IsRefining() and sizes(table) == sizes(expected) and
            numpy.array_equal(entries(table), entries(expected)),
            "%s: the next update with the same key takes the measured table" % name)
    requests = sizing.GetRefiner().GetNumberOfRequests()
    sizing.Update(key, data, image, scalars, table, order, step, 4097, True)
    c.check(sizing.GetRefiner().GetNumberOfRequests() == requests and not sizing.IsRefining(),
            "%s: the same key again changes nothing" % name)
    sizing.SetRefineInBackground(False)
    sizing.Update([2.0, float(order)], data, image, scalars, table, order, step, 4097, True)
    c.check(not sizing.IsRefining() and sizes(table) == sizes(expected),
            "%s: without background refinement, sizes measured at once" % name)

# New data alone (time steps): the measured sizes and range are kept for values inside that
# range whose distribution and chords are close; new values outside it, or a distribution far
# from it, are measured again.
def step_of(function):
    out = vtkImageData()
    out.DeepCopy(image)
    values = vtk_to_numpy(out.GetPointData().GetScalars())
    values[:] = function(values)
    out.GetPointData().GetScalars().Modified()
    return out


for order in (1, 2):
    name = "order %d, time steps" % order
    sizing = hovr.vtkPreIntegrationTableSizing()
    table = make_table(prop, order)
    key = [3.0, float(order)]

    def update(volume, data):
        table.SetScalarRange(*volume.GetPointData().GetScalars().GetRange())
        return sizing.Update(key, data, volume, volume.GetPointData().GetScalars(), table, order,
                             step, 4097, True)

    update(image, [1.0])
    measured = sizes(table), table.GetScalarRange()
    close = step_of(lambda v: low + 0.99 * (v - low))
    c.check(update(close, [2.0]) and sizing.GetNumberOfKeptSizes() == 1 and
            (sizes(table), table.GetScalarRange()) == measured,
            "%s: a close step inside the range keeps the sizes and the range (shift %.4f, chords "
            "%.3f)" % (name, sizing.GetLastDistributionShift(), sizing.GetLastChordChange()))
    beyond = step_of(lambda v: low + 1.005 * (v - low))
    n, r = measured[0][0], measured[1]
    spacing = (r[1] - r[0]) / (n - 1)
    extra = math.ceil((beyond.GetPointData().GetScalars().GetRange()[1] - r[1]) / spacing - 1e-9)
    c.check(update(beyond, [2.5]) and sizing.GetNumberOfKeptSizes() == 2 and
            table.GetTableSize() == n + extra and
            abs(table.GetScalarRange()[1] - (r[1] + extra * spacing)) <= 1e-9 * (r[1] - r[0]),
            "%s: values a little beyond the range extend it by %d whole spacings, the sizes "
            "kept" % (name, extra))
    outside = step_of(lambda v: low + 1.5 * (v - low))
    c.check(update(outside, [3.0]) and sizing.GetNumberOfKeptSizes() == 2 and
            table.GetScalarRange() == outside.GetPointData().GetScalars().GetRange(),
            "%s: values outside the measured range are measured again" % name)
    update(image, [4.0])
    far = step_of(lambda v: low + (v - low) ** 3 / (high - low) ** 2)
    c.check(update(far, [5.0]) and sizing.GetNumberOfKeptSizes() == 2 and
            sizing.GetLastDistributionShift() > sizing.GetMaximumDistributionShift(),
            "%s: a distribution shifted by %.3f of the range is measured again" % (
                name, sizing.GetLastDistributionShift()))

# Provisional results: the last measured sizes, built for an edit, before its measurement.
for order in (1, 2):
    name = "order %d, provisional" % order
    measured = make_table(prop, order)
    hovr.vtkPreIntegrationTableSizer().Choose(image, scalars, measured, order, step)
    edited = make_property(0.5)  # an edit of the spike's height
    # What the edit measures, and its kept sizes built for it, in the calling thread.
    # Many rays: the measurement lasts long enough for the provisional result to be seen.
    sizer = hovr.vtkPreIntegrationTableSizer()
    sizer.SetNumberOfRays(32768)
    expected = make_table(edited, order)
    sizer.Choose(image, scalars, expected, order, step)
    expected.Update()
    kept = make_table(edited, order)
    for setter, value in (("SetTableSize", measured.GetTableSize()),
                          ("SetChordSize", measured.GetChordSize()),
                          ("SetChordRange", measured.GetChordRange()),
                          ("SetDeviationSize", measured.GetDeviationSize()),
                          ("SetDeviationRange", measured.GetDeviationRange())):
        getattr(kept, setter)(value)
    kept.SetPrefilter(measured.GetPrefilter())
    kept.Update()
    refiner = hovr.vtkPreIntegrationTableRefiner()
    refiner.GetSizerSettings().SetNumberOfRays(32768)
    request_table = make_table(edited, order)
    for setter in ("TableSize", "ChordSize", "ChordRange", "DeviationSize", "DeviationRange",
                   "Prefilter"):
        getattr(request_table, "Set" + setter)(getattr(measured, "Get" + setter)())
    request = refiner.Request(image, scalars, request_table, order, step, 4097, True, True)
    table = make_table(edited, order)
    seen = False
    while not seen:
        if refiner.IsProvisional(request):
            seen = refiner.TakeResult(request, table)
        elif ((refiner.IsReady(request) and not refiner.IsProvisional(request)) or
              (not refiner.IsBusy() and not refiner.IsReady(request))):
            break  # the measured result (or a failure) came first
    c.check(seen, "%s: a provisional result before the measurement ends (%s)" % (
        name, refiner.GetFailure(request)))
    if seen:
        c.check(sizes(table) == sizes(measured) and
                numpy.array_equal(entries(table), entries(kept)),
                "%s: the provisional table is the measured sizes built for the edit" % name)
    refiner.Wait()
    c.check(refiner.IsReady(request) and not refiner.IsProvisional(request),
            "%s: then the measured result" % name)
    c.check(refiner.TakeResult(request, table), "%s: the measured result is taken" % name)
    c.check(sizes(table) == sizes(expected), "%s: the measured sizes %s are the calling "
            "thread's %s" % (name, sizes(table), sizes(expected)))
    table.Update()
    c.check(numpy.array_equal(entries(table), entries(expected)),
            "%s: the final entries are those of the measured table" % name)
    # Not taken: only the measured result waits.
    request = refiner.Request(image, scalars, request_table, order, step, 4097, True, True)
    refiner.Wait()
    c.check(refiner.IsReady(request) and not refiner.IsProvisional(request) and
            not refiner.IsConfirmation(request),
            "%s: a provisional result not taken gives way to the measured one" % name)
    other = make_table(edited, order)
    c.check(refiner.TakeResult(request, other) and sizes(other) == sizes(expected) and
            numpy.array_equal(entries(other), entries(expected)),
            "%s: the same table as without the provisional one" % name)
    # The same sizes measured again: the final result changes nothing.
    again = make_table(edited, order)
    for setter in ("TableSize", "ChordSize", "ChordRange", "DeviationSize", "DeviationRange",
                   "Prefilter"):
        getattr(again, "Set" + setter)(getattr(expected, "Get" + setter)())
    request = refiner.Request(image, scalars, again, order, step, 4097, True, True)
    first = False
    while not first:
        if refiner.IsProvisional(request):
            first = refiner.TakeResult(request, again)
        elif ((refiner.IsReady(request) and not refiner.IsProvisional(request)) or
              (not refiner.IsBusy() and not refiner.IsReady(request))):
            break
    refiner.Wait()
    builds = again.GetBuildCount()
    c.check(first and refiner.IsReady(request) and refiner.IsConfirmation(request) and
            refiner.TakeResult(request, again) and not refiner.IsConfirmation(request) and
            again.GetBuildCount() == builds and sizes(again) == sizes(expected) and
            numpy.array_equal(entries(again), entries(expected)),
            "%s: the same sizes measured: the provisional table stays" % name)
    del refiner

# A provisional request whose table holds a complete build at the kept sizes takes its entries
# (the caller draws interim sizes meanwhile), and the provisional table integrates only those
# that read what the edit reached, equal to that table built from scratch. Held (Paused) and
# superseded by a second edit before it starts, the request's entries go to the next one.
for order in (1, 2):
    name = "order %d, from the caller's entries" % order
    edited = make_property()
    measured = make_table(edited, order)
    hovr.vtkPreIntegrationTableSizer().Choose(image, scalars, measured, order, step)
    held = make_table(edited, order)
    for setter in ("TableSize", "ChordSize", "ChordRange", "DeviationSize", "DeviationRange",
                   "Prefilter"):
        getattr(held, "Set" + setter)(getattr(measured, "Get" + setter)())
    held.Update()
    total = held.GetNumberOfEntries()
    function = edited.GetScalarOpacity()
    node = [0.0] * 4
    refiner = hovr.vtkPreIntegrationTableRefiner()
    refiner.SetPaused(True)
    requests = []
    for height in (0.5, 0.45):
        function.GetNodeValue(function.GetSize() // 2, node)
        node[1] = height
        function.SetNodeValue(function.GetSize() // 2, node)
        requests.append(refiner.Request(image, scalars, held, order, step, 4097, True, True))
        if len(requests) == 1:
            c.check(held.GetTable().GetNumberOfTuples() == 0,
                    "%s: the request takes the table's entries" % name)
    refiner.SetPaused(False)
    table = make_table(edited, order)
    seen = False
    while not seen:
        if refiner.IsProvisional(requests[-1]):
            seen = refiner.TakeResult(requests[-1], table)
        elif ((refiner.IsReady(requests[-1]) and not refiner.IsProvisional(requests[-1])) or
              (not refiner.IsBusy() and not refiner.IsReady(requests[-1]))):
            break
    refiner.Wait()
    fresh = make_table(edited, order)
    for setter in ("TableSize", "ChordSize", "ChordRange", "DeviationSize", "DeviationRange",
                   "Prefilter"):
        getattr(fresh, "Set" + setter)(getattr(measured, "Get" + setter)())
    fresh.Update()
    c.check(seen and 0 < table.GetLastBuildEntries() < total and
            numpy.array_equal(entries(table), entries(fresh)),
            "%s: the provisional table integrated %d of %d entries, equal to a fresh build" % (
                name, table.GetLastBuildEntries(), total))
    c.check(refiner.GetNumberOfStopped() == 1, "%s: the first request was stopped" % name)
    del refiner

# GetNumberOfEntriesToBuild predicts the entries the next build integrates: all of them before
# a first build and after a change of sizes, those reaching the changed samples after an
# opacity edit (fewer than all), none when nothing changed.
for order in (1, 2):
    edited = make_property()
    table = make_table(edited, order)
    table.SetTableSize(129)
    table.SetChordSize(33)
    table.SetDeviationSize(9 if order == 2 else 1)
    predicted = [table.GetNumberOfEntriesToBuild()]
    table.Update()
    built = [table.GetLastBuildEntries()]
    function = edited.GetScalarOpacity()
    node = [0.0] * 4
    function.GetNodeValue(function.GetSize() // 2, node)
    node[1] = 0.5 * node[1] + 0.1
    function.SetNodeValue(function.GetSize() // 2, node)
    predicted.append(table.GetNumberOfEntriesToBuild())
    table.Update()
    built.append(table.GetLastBuildEntries())
    predicted.append(table.GetNumberOfEntriesToBuild())
    total = table.GetNumberOfEntries()
    c.check(predicted[:2] == built and predicted[0] == total and 0 < predicted[1] < total and
            predicted[2] == 0, "order %d: the entries to build predicted %s, built %s of %d" % (
                order, predicted, built, total))

# A refiner deleted while it measures: the worker stops at its next check.
big = hovr.vtkMarschnerLobbSource()
big.SetDimensions(96, 96, 96)
big.Update()
refiner = hovr.vtkPreIntegrationTableRefiner()
refiner.Request(big.GetOutput(), big.GetOutput().GetPointData().GetScalars(),
                make_table(prop, 2), 2, step, 4097, True)
del refiner  # would hang here (ctest's timeout) if the worker did not stop
print("a refiner deleted during a measurement returned")
c.finish()
