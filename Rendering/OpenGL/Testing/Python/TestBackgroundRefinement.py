"""Answer first, refine after: vtkPreIntegrationVolumeMapper with RefineInBackground.

On the Marschner-Lobb volume (64^3, generated here) with a spike transfer function, 96 x 96,
for both orders:
- a drag of 20 opacity edits, rendered one after the other while the worker is held
  (vtkPreIntegrationTableRefiner::SetPaused): no frame can wait for a measurement, since none
  runs; every frame is drawn (with interim sizes within InterimEntries, or the last measured
  sizes rebuilt incrementally at once), the mapper says it is refining, the 20 superseded
  requests are counted as stopped and none completed;
- released, the worker measures the last edit only; CheckRefinement() fires
  TablesRefinedEvent once (none when the measurement confirms the sizes drawn at once), and
  the next frame draws the refined table: the same sizes as a
  mapper that measures at once (RefineInBackground off) for the final transfer function, and
  the same image (float capture, within 1e-6: the same table and ray walk);
- with the worker running, a second drag of 20 edits ends on the refined image of its last
  edit too (after WaitForRefinement());
- a small edit whose measurement confirms the provisional table drawn for it ends the
  refinement by itself: no frame, no event, and the image drawn is the measured-at-once one;
- a change of sample distance, and new data whose values leave the measured range, are
  answered the same way: an interim frame, then the refined one equal to the measured-at-once
  image;
- a time step close to the measured one (values inside its range, 0.99 times the first)
  keeps the measured sizes and range, with no interim frame, and draws what a mapper that
  measures at once and saw the same steps draws;
- the interim tables stay within InterimEntries entries;
- the mapper times its draws (vtkExtensibleGPUVolumeRayCastMapper::GetLastDrawTime) and gives
  the sizing that frame time, against which a provisional table's rebuild is weighed.
"""

import time

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkRenderWindow, vtkRenderer,
                                         vtkVolume, vtkVolumeProperty)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401

import hovr
from hovrtesting import Checker

c = Checker()
SIZE = 96


def volume(n):
    source = hovr.vtkMarschnerLobbSource()
    source.SetDimensions(n, n, n)
    source.Update()
    image = vtkImageData()
    image.DeepCopy(source.GetOutput())
    return image


def scaled(image, factor):
    """A time step: the volume's values times factor."""
    out = vtkImageData()
    out.DeepCopy(image)
    values = vtk_to_numpy(out.GetPointData().GetScalars())
    values *= factor
    out.GetPointData().GetScalars().Modified()
    return out


def make_property(low, high):
    opacity = vtkPiecewiseFunction()
    color = vtkColorTransferFunction()
    span = high - low
    for x, a in ((0.0, 0.0), (0.28, 0.0), (0.3, 0.6), (0.32, 0.0), (0.68, 0.0), (0.7, 0.9),
                 (0.72, 0.0), (1.0, 0.0)):
        opacity.AddPoint(low + x * span, a)
    color.AddRGBPoint(low, 0.1, 0.3, 1.0)
    color.AddRGBPoint(high, 1.0, 0.6, 0.1)
    prop = vtkVolumeProperty()
    prop.SetScalarOpacity(opacity)
    prop.SetColor(color)
    prop.SetInterpolationTypeToLinear()
    prop.SetScalarOpacityUnitDistance(0.05)
    return prop


def edit(prop, low, high, k):
    """Opacity edit k of a drag: the second spike's peak moves up."""
    prop.GetScalarOpacity().AddPoint(low + 0.7 * (high - low), 0.3 + 0.03 * k)


class View:
    """One window with one volume and a float capture."""

    def __init__(self, mapper, image, prop):
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetMultiSamples(0)
        self.window.SetAlphaBitPlanes(1)
        self.window.SetSize(SIZE, SIZE)
        self.renderer = vtkRenderer()
        self.renderer.SetBackgroundAlpha(0.0)
        self.window.AddRenderer(self.renderer)
        self.volume = vtkVolume()
        self.volume.SetMapper(mapper)
        self.volume.SetProperty(prop)
        self.renderer.AddVolume(self.volume)
        mapper.SetInputData(image)
        self.mapper = mapper
        self.renderer.ResetCamera()
        self.renderer.GetActiveCamera().Azimuth(30)
        self.renderer.GetActiveCamera().Elevation(20)
        self.renderer.ResetCameraClippingRange()
        self.capture = hovr.vtkFloatRGBARenderCapture()
        self.window.Render()
        self.capture.Attach(self.window)

    def image(self):
        self.window.Render()
        out = vtkImageData()
        self.capture.Capture(out)
        return vtk_to_numpy(out.GetPointData().GetScalars()).copy()

    def close(self):
        self.window.Finalize()


def sizes(mapper):
    table = mapper.GetActiveTable()
    return (table.GetTableSize(), table.GetChordSize(), table.GetDeviationSize())


def measured_at_once(order, image, prop, step):
    """The image and sizes of a mapper that measures before the frame."""
    mapper = hovr.vtkPreIntegrationVolumeMapper()
    mapper.SetIntegration(order)
    mapper.SetSampleDistance(step)
    view = View(mapper, image, prop)
    pixels = view.image()
    result = (pixels, sizes(mapper))
    view.close()
    return result


image = volume(64)
low, high = image.GetScalarRange()
step = image.GetSpacing()[0]
for order in (1, 2):
    name = "order %d" % order
    prop = make_property(low, high)
    mapper = hovr.vtkPreIntegrationVolumeMapper()
    mapper.SetIntegration(order)
    mapper.SetSampleDistance(step)
    mapper.SetRefineInBackground(True)
    refined_events = []
    mapper.AddObserver(mapper.TablesRefinedEvent, lambda *args: refined_events.append(1))
    sizing = mapper.GetTableSizing()
    refiner = sizing.GetRefiner()
    view = View(mapper, image, prop)
    c.check(mapper.GetRefining(), "%s: the first frame is drawn with interim sizes" % name)
    mapper.WaitForRefinement()
    c.check(mapper.CheckRefinement() and len(refined_events) == 1,
            "%s: TablesRefinedEvent once the first measurement is done" % name)
    view.image()
    c.check(not mapper.GetRefining(), "%s: the next frame draws the measured table" % name)
    # The draw time the sizing weighs a rebuild against: the timer query of a draw before.
    view.image()
    c.check(mapper.GetLastDrawTime() > 0.0 and mapper.GetTableSizing().GetFrameTime() > 0.0,
            "%s: the mapper times its draws (%.4f s) and gives the sizing that frame time" % (
                name, mapper.GetLastDrawTime()))

    # The drag, the worker held: every frame must be drawn without a measurement.
    refiner.SetPaused(True)
    before = (refiner.GetNumberOfRequests(), refiner.GetNumberOfCompleted(),
              refiner.GetNumberOfStopped(), sizing.GetNumberOfInterimTables())
    measured = sizes(mapper)
    provisional = sizing.GetNumberOfProvisionalTables()
    drawn = 0
    cheap = 0
    for k in range(20):
        edit(prop, low, high, k)
        pixels = view.image()
        drawn += int(mapper.GetRefining() and pixels[:, 3].max() > 0)
        table = mapper.GetActiveTable()
        # Interim sizes within InterimEntries, or the last measured sizes drawn at once,
        # rebuilt incrementally (or within InterimEntries entries).
        cheap += int(table.GetNumberOfEntries() <= sizing.GetInterimEntries() or
                     (sizes(mapper) == measured and
                      table.GetLastBuildEntries() < table.GetNumberOfEntries()))
    c.check(drawn == 20, "%s: 20 edits drawn while the worker is held (%d)" % (name, drawn))
    c.check(cheap == 20, "%s: every frame of the drag an interim table within %d entries or the "
            "last measured sizes rebuilt incrementally (%d)" % (
                name, sizing.GetInterimEntries(), cheap))
    c.check(sizing.GetNumberOfInterimTables() - before[3] +
            sizing.GetNumberOfProvisionalTables() - provisional == 20,
            "%s: 20 interim or provisional tables drawn at once (%d interim)" % (
                name, sizing.GetNumberOfInterimTables() - before[3]))
    c.check(refiner.GetNumberOfRequests() - before[0] == 20 and
            refiner.GetNumberOfCompleted() == before[1] and
            refiner.GetNumberOfStopped() - before[2] == 19,
            "%s: 20 requests, none measured, the 19 superseded ones stopped (%d, %d, %d)" % (
                name, refiner.GetNumberOfRequests() - before[0],
                refiner.GetNumberOfCompleted() - before[1],
                refiner.GetNumberOfStopped() - before[2]))
    c.check(not mapper.CheckRefinement(), "%s: no refined table while held" % name)
    refiner.SetPaused(False)
    mapper.WaitForRefinement()
    confirmed = not mapper.GetRefining()  # the measured sizes are the ones drawn at once
    c.check((confirmed and not mapper.CheckRefinement() and len(refined_events) == 1) or
            (mapper.CheckRefinement() and len(refined_events) == 2),
            "%s: TablesRefinedEvent once the last edit is measured, or none when the "
            "measurement confirms the sizes drawn (%s)" % (name, confirmed))
    c.check(refiner.GetNumberOfCompleted() - before[1] == 1,
            "%s: only the last edit measured" % name)
    refined = view.image()
    reference, reference_sizes = measured_at_once(order, image, prop, step)
    difference = float(numpy.abs(refined - reference).max())
    print("%s: interim sizes %s, refined %s, measured at once %s; largest difference %.2e; "
          "refinement took %.3f s" % (name, measured, sizes(mapper), reference_sizes, difference,
                                      refiner.GetLastRefinementTime()))
    c.check(sizes(mapper) == reference_sizes, "%s: the refined sizes %s are the measured ones "
            "%s" % (name, sizes(mapper), reference_sizes))
    c.check(difference <= 1e-6, "%s: the refined image is the measured-at-once image (%.2e)"
            % (name, difference))

    # A drag with the worker running: the image after it is the refined one of its last edit.
    for k in range(20, 40):
        edit(prop, low, high, k)
        view.image()
    mapper.WaitForRefinement()
    refined = view.image()
    reference, reference_sizes = measured_at_once(order, image, prop, step)
    c.check(not mapper.GetRefining() and sizes(mapper) == reference_sizes and
            float(numpy.abs(refined - reference).max()) <= 1e-6,
            "%s: after a drag with the worker running, the refined image of the last edit" % name)

    # A small edit whose measurement confirms the provisional table (its last measured sizes,
    # built for the edit and drawn, at once when their rebuild is cheap, else by the worker):
    # the refinement ends without another frame or event, and the image drawn is the
    # measured-at-once one. A worker's provisional table must be drawn before the measurement
    # ends: an edit whose measurement ended first is tried again.
    opacity = prop.GetScalarOpacity()
    nodes = [[0.0] * 4 for _ in range(opacity.GetSize())]
    for i, node in enumerate(nodes):
        opacity.GetNodeValue(i, node)
    peak = max(range(len(nodes)), key=lambda i: nodes[i][1])
    for attempt in range(5):
        nodes[peak][1] *= 0.999
        opacity.SetNodeValue(peak, nodes[peak])
        provisional = sizing.GetNumberOfProvisionalTables()
        drawn = view.image()
        if sizing.GetNumberOfProvisionalTables() == provisional + 1:
            break  # drawn at once
        while mapper.GetRefining() and not mapper.GetRefinementReady():
            time.sleep(0.002)
        drawn = view.image()
        if sizing.GetNumberOfProvisionalTables() == provisional + 1:
            break
        mapper.WaitForRefinement()
        view.image()
    events = len(refined_events)
    mapper.WaitForRefinement()
    refining = mapper.GetRefining()
    reference, reference_sizes = measured_at_once(order, image, prop, step)
    c.check(sizing.GetNumberOfProvisionalTables() == provisional + 1 and not refining and
            not mapper.CheckRefinement() and len(refined_events) == events and
            sizes(mapper) == reference_sizes and
            float(numpy.abs(drawn - reference).max()) <= 1e-6,
            "%s: a measurement that confirms the provisional table ends the refinement without "
            "a frame, on the measured-at-once image (%d attempts)" % (name, attempt + 1))

    # A new sample distance, then new data whose values leave the measured range (a time
    # step whose sizes must be measured again).
    for what, change in (("sample distance", lambda: mapper.SetSampleDistance(0.5 * step)),
                         ("data", lambda: mapper.SetInputData(scaled(image, 1.5)))):
        change()
        view.image()
        interim = mapper.GetRefining()
        mapper.WaitForRefinement()
        refined = view.image()
        reference, reference_sizes = measured_at_once(order, mapper.GetInput(), prop,
                                                      mapper.GetSampleDistance())
        c.check(interim and sizes(mapper) == reference_sizes and
                float(numpy.abs(refined - reference).max()) <= 1e-6,
                "%s, new %s: an interim frame, then the measured-at-once image" % (name, what))
    # A time step close to the measured one (inside its range, a similar distribution): the
    # sizes and range are kept, no interim frame, the image is the one of a mapper that
    # measures at once and saw the same two steps.
    mapper.SetSampleDistance(step)
    mapper.SetInputData(image)
    view.image()
    mapper.WaitForRefinement()
    view.image()
    sizing = mapper.GetTableSizing()
    kept = sizing.GetNumberOfKeptSizes()
    mapper.SetInputData(scaled(image, 0.99))
    pixels = view.image()
    blocking = hovr.vtkPreIntegrationVolumeMapper()
    blocking.SetIntegration(order)
    blocking.SetSampleDistance(step)
    other = View(blocking, image, prop)
    blocking.SetInputData(scaled(image, 0.99))
    reference = other.image()
    other.close()
    c.check(sizing.GetNumberOfKeptSizes() == kept + 1 and not mapper.GetRefining() and
            float(numpy.abs(pixels - reference).max()) <= 1e-6,
            "%s, a close time step: the measured sizes kept (shift %.4f, chords %.3f), the "
            "image of a mapper that measures at once" % (
                name, sizing.GetLastDistributionShift(), sizing.GetLastChordChange()))
    mapper.SetInputData(image)
    mapper.SetSampleDistance(step)
    view.close()
c.finish()
