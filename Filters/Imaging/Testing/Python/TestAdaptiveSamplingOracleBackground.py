"""vtkAdaptiveSamplingOracle with RefineInBackground: answer first with the last distances,
compute the new ones in a worker thread, the newest update winning.

Every refined output is compared with a filter that computes in the foreground on the same
input and opacity function (the distances must be equal, float for float), and every interim
output must hold the distances output before (the same array), at once. Covered: the first
update (computed at once), an opacity edit, a drag of edits without waiting (only the last is
output after the wait), a new time step on the same grid (the range volumes computed again), a
new grid and a new setting (computed at once), CheckRefinement's event (once per result), an
unchanged function set again (nothing recomputed), a bad input reported on the caller's thread,
turning the mode off and deleting the filter while a computation runs.
"""

import time

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction

import hovr
from hovrtesting import Checker, Messages

c = Checker()
NAME = "OracleDistance"


def volume(points, alpha=0.25):
    source = hovr.vtkMarschnerLobbSource()
    source.SetDimensions(points, points, points)
    source.SetAlpha(alpha)
    source.Update()
    image = vtkImageData()
    image.ShallowCopy(source.GetOutput())
    return image


def opacity_function(low, high):
    function = vtkPiecewiseFunction()
    for x, a in ((0.0, 0.0), (0.45, 0.0), (0.5, 0.2), (0.55, 0.0), (0.75, 0.0), (0.8, 0.6),
                 (0.85, 0.0), (1.0, 0.0)):
        function.AddPoint(low + x * (high - low), a)
    return function


def distances(oracle):
    array = oracle.GetOutput().GetPointData().GetArray(NAME)
    return array


def foreground(image, function, epsilon=0.002):
    """The distances a filter computing in the foreground gives (numpy)."""
    reference = hovr.vtkAdaptiveSamplingOracle()
    reference.SetInputData(image)
    copy = vtkPiecewiseFunction()
    copy.DeepCopy(function)
    reference.SetScalarOpacity(copy)
    reference.SetEpsilon(epsilon)
    reference.Update()
    return vtk_to_numpy(distances(reference)).copy()


def same(oracle, expected, what):
    array = distances(oracle)
    got = vtk_to_numpy(array) if array is not None else None
    c.check(got is not None and got.shape == expected.shape and numpy.array_equal(got, expected),
            what + ": the distances of a filter computing in the foreground")


image = volume(64)
low, high = image.GetScalarRange()
function = opacity_function(low, high)
oracle = hovr.vtkAdaptiveSamplingOracle()
c.check(not oracle.GetRefineInBackground(), "RefineInBackground is off by default")
oracle.SetInputData(image)
oracle.SetScalarOpacity(function)
oracle.SetRefineInBackground(True)
messages = Messages(oracle)
events = []
oracle.AddObserver(oracle.OracleRefinedEvent, lambda *args: events.append(1))

# The first update has nothing to answer with: it computes.
oracle.Update()
c.check(not oracle.GetRefining(), "first update: computed at once, nothing refining")
same(oracle, foreground(image, function), "first update")
c.check(oracle.GetLastRecomputedRanges(), "first update: the range volumes computed")

# An opacity edit: the last distances at once, the new ones after the wait.
before = distances(oracle)
function.AddPoint(low + 0.3 * (high - low), 0.4)
oracle.Update()
c.check(oracle.GetRefining(), "opacity edit: refining")
c.check(distances(oracle) is before, "opacity edit: the interim output holds the last distances")
oracle.WaitForRefinement()
c.check(oracle.GetRefining(), "opacity edit: still refining until the next update")
oracle.Update()
c.check(not oracle.GetRefining(), "opacity edit: refined after the next update")
same(oracle, foreground(image, function), "opacity edit")
c.check(not oracle.GetLastRecomputedRanges(), "opacity edit: the range volumes kept")

# CheckRefinement fires its event once per result and marks the filter modified.
function.AddPoint(low + 0.3 * (high - low), 0.1)
oracle.Update()
deadline = time.time() + 60.0
while not oracle.CheckRefinement() and time.time() < deadline:
    time.sleep(0.005)
c.check(events == [1], "CheckRefinement fires OracleRefinedEvent once (got %d)" % len(events))
c.check(not oracle.CheckRefinement(), "CheckRefinement: false once the result was announced")
c.check(oracle.GetRefinementReady(), "the result waits for the next update")
c.check(oracle.GetRefinementProgress() == 1.0, "progress 1 when the result waits")
modified = oracle.GetMTime()
oracle.Update()
c.check(not oracle.GetRefining(), "CheckRefinement: the next update takes the result")
same(oracle, foreground(image, function), "after CheckRefinement")
oracle.Update()
c.check(oracle.GetMTime() == modified and not oracle.GetRefining(),
        "an update without a change recomputes nothing")

# The same function set again, as ParaView does: nothing to refine.
copy = vtkPiecewiseFunction()
copy.DeepCopy(function)
oracle.SetScalarOpacity(copy)
kept = distances(oracle)
oracle.Update()
c.check(not oracle.GetRefining() and distances(oracle) is kept,
        "an unchanged function set again: the same distances, nothing refining")
oracle.SetScalarOpacity(function)

# A drag: every update answers at once with the distances output before the drag.
big = volume(96)
oracle.SetInputData(big)
oracle.Update()  # a new grid: computed at once
c.check(not oracle.GetRefining(), "new grid: computed at once")
same(oracle, foreground(big, function), "new grid")
before = distances(oracle)
for k in range(20):
    function.AddPoint(low + 0.8 * (high - low), 0.3 + 0.02 * k)
    oracle.Update()
    c.check(distances(oracle) is before, "drag edit %d: the interim distances" % k)
c.check(oracle.GetRefining(), "drag: refining after the last edit")
oracle.WaitForRefinement()
oracle.Update()
same(oracle, foreground(big, function), "after the drag (the last edit's)")

# A new time step on the same grid: the last distances at once, the ranges computed again.
step = volume(96, alpha=0.3)
before = distances(oracle)
oracle.SetInputData(step)
oracle.Update()
c.check(oracle.GetRefining() and distances(oracle) is before,
        "new time step: the last distances at once")
oracle.WaitForRefinement()
oracle.Update()
same(oracle, foreground(step, function), "new time step")
c.check(oracle.GetLastRecomputedRanges(), "new time step: the range volumes computed again")

# A new setting: computed at once.
oracle.SetEpsilon(0.05)
oracle.Update()
c.check(not oracle.GetRefining(), "new Epsilon: computed at once")
same(oracle, foreground(step, function, 0.05), "new Epsilon")

# A bad input is reported on the caller's thread, with an empty output.
bad = vtkImageData()
bad.SetDimensions(8, 8, 8)
oracle.SetInputData(bad)
oracle.Update()
c.check(messages.errors and distances(oracle) is None,
        "bad input in the background mode: an error and no distances (%s)" % messages.errors)
messages.errors.clear()

# Off while a computation runs, and deleted while one runs: no crash, no stale result.
oracle.SetInputData(big)
oracle.Update()
function.AddPoint(low + 0.6 * (high - low), 0.5)
oracle.Update()
c.check(oracle.GetRefining(), "refining before turning the mode off")
oracle.SetRefineInBackground(False)
c.check(not oracle.GetRefining(), "off: nothing refining")
oracle.Update()
same(oracle, foreground(big, function, 0.05), "off: computed at once")
oracle.SetRefineInBackground(True)
oracle.Update()
function.AddPoint(low + 0.6 * (high - low), 0.2)
oracle.Update()
del oracle
c.check(not messages.errors and not messages.warnings,
        "no other message (%s %s)" % (messages.errors, messages.warnings))
c.finish()
