"""When memory runs out for a copy of the volume, never an exception through the pipeline
(which aborts Python, pvbatch or any VTK application):
- object-order ray casting (float bricks and octree): an error that says how much the bricks
  take and an empty image; the copies are freed. In a window, vtkObjectOrderVolumeMapper then
  draws with vtkFixedPointVolumeRayCastMapper after one warning, does not try the allocation
  again on later frames, and returns to the caster when the scalars change and memory
  suffices;
- the reference integrator reads the volume in place (vtkVolumeScalarView), so within the same
  limit it draws its image, with no error;
- a 3D pre-integration table built on the CPU: Update() is false, with an error that gives
  the table's size;
- the analytic mapper's packed corners (4 values per point): one warning, and the cells are
  read from VTK's volume texture instead, giving the image CornerPacking off gives.

Memory is limited with the process's address-space limit (RLIMIT_AS), set to what the
process uses plus HEADROOM once the window, the threads and the volume exist: the volume's
copies take more than that headroom, VTK's own mappers need far less.
"""

import sys

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkVolume, vtkVolumeProperty,
                                         vtkWindowToImageFilter)

import hovr
from hovr import io as hio
from hovrtesting import Checker, Messages, offscreen_window

try:
    import resource
    SOFT, HARD = resource.getrlimit(resource.RLIMIT_AS)
except (ImportError, AttributeError, ValueError) as error:
    print("skipped: no address-space limit on this platform (%s)" % error)
    sys.exit(125)

c = Checker()
SIZE = (96, 80)
HEADROOM = 160 * 2 ** 20
POINTS = 400  # 400^3 uint8: 61 MiB of data
# Its float bricks: 8^3 cells each with their far faces (9^3 points), 348 MiB.
BRICKS_MIB = -(-((POINTS - 2) // 8 + 1) ** 3 * 9 ** 3 * 4 // 2 ** 20)


def address_space():
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    return None


def volume(points):
    image = vtkImageData()
    image.SetDimensions(points, points, points)
    image.SetSpacing(1.0 / points, 1.0 / points, 1.0 / points)
    values = (numpy.arange(points ** 3, dtype=numpy.uint32) % 251).astype(numpy.uint8)
    image.GetPointData().SetScalars(numpy_to_vtk(values, deep=1))
    return image


def limited(action):
    """Runs action() with the address space limited to its current size plus HEADROOM."""
    resource.setrlimit(resource.RLIMIT_AS, (address_space() + HEADROOM, HARD))
    try:
        return action()
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (SOFT, HARD))


if address_space() is None or (HARD != resource.RLIM_INFINITY and HARD < 2 ** 33):
    print("skipped: /proc/self/status or a raisable address-space limit is missing")
    sys.exit(125)

color = vtkColorTransferFunction()
color.AddRGBPoint(0.0, 0.2, 0.4, 1.0)
color.AddRGBPoint(255.0, 1.0, 0.8, 0.2)
opacity = vtkPiecewiseFunction()
opacity.AddPoint(0.0, 0.0)
opacity.AddPoint(255.0, 0.8)
prop = hio.make_volume_property(color, opacity, 0.05)
small, big = volume(16), volume(POINTS)
step = 1.0 / POINTS

# The caster alone. A first update on a small volume starts the threads (their stacks and
# arenas are address space too).
caster = hovr.vtkObjectOrderRayCaster()
messages = Messages(caster)
caster.SetVolumeProperty(prop)
caster.SetImageSize(*SIZE)
caster.SetSampleDistance(step)
caster.SetInputData(small)
caster.SetCamera(hio.default_camera(small.GetBounds(), parallel=True))
caster.Update()
c.check(not messages.errors and caster.GetMemorySize() > 0, "a small volume renders")
caster.SetInputData(big)
caster.SetCamera(hio.default_camera(big.GetBounds(), parallel=True))
limited(caster.Update)
print("caster:", messages.errors)
rgba = vtk_to_numpy(caster.GetOutput().GetPointData().GetScalars())
c.check(caster.GetLastUpdateOutOfMemory() and len(messages.errors) == 1 and
        "Not enough memory" in messages.errors[0] and
        "%d x %d x %d" % (POINTS, POINTS, POINTS) in messages.errors[0] and
        "%d MiB" % BRICKS_MIB in messages.errors[0],
        "out of memory: one error naming the volume and the bricks' size")
c.check(rgba.shape == (SIZE[0] * SIZE[1], 4) and not rgba.any(),
        "out of memory: the image is empty")
c.check(caster.GetMemorySize() < 2 ** 20 and caster.ComputeNonTransparentCells() == -1,
        "out of memory: the copies are freed (%d bytes left)" % caster.GetMemorySize())
caster.Modified()  # as after any error: the next update after a change tries again
caster.Update()
c.check(not caster.GetLastUpdateOutOfMemory() and len(messages.errors) == 1 and
        vtk_to_numpy(caster.GetOutput().GetPointData().GetScalars())[:, 3].max() > 0.1,
        "with memory back, the next update renders the volume")
del caster

# The mapper in a window.
window, view = offscreen_window(SIZE)
mapper = hovr.vtkObjectOrderVolumeMapper()
mapper.SetSampleDistance(step)
mapper.SetInputData(small)
messages = Messages(mapper)
actor = vtkVolume()
actor.SetMapper(mapper)
actor.SetProperty(prop)
view.AddVolume(actor)
view.GetActiveCamera().DeepCopy(hio.default_camera(big.GetBounds(), parallel=True))
view.ResetCameraClippingRange(big.GetBounds())
window.Render()
c.check(not mapper.GetLastFrameFellBack() and not messages.errors, "the mapper draws")
mapper.SetInputData(big)


def pixels():
    capture = vtkWindowToImageFilter()
    capture.SetInput(window)
    capture.Update()
    return vtk_to_numpy(capture.GetOutput().GetPointData().GetScalars()).copy()


def frames():
    window.Render()
    first = mapper.GetLastFrameFellBack()
    window.Render()
    return first, pixels().max()


fell_back, brightest = limited(frames)
print("mapper: errors", messages.errors, "warnings", messages.warnings, "fell back", fell_back,
      "brightest", brightest)
c.check(fell_back and mapper.GetLastFrameFellBack() and brightest > 0,
        "out of memory: both frames drawn by vtkFixedPointVolumeRayCastMapper")
c.check(len(messages.errors) == 1 and "Not enough memory" in messages.errors[0],
        "the caster's error once: the second frame does not try again")
c.check(len(messages.warnings) == 1 and "not enough memory" in messages.warnings[0] and
        "vtkFixedPointVolumeRayCastMapper" in messages.warnings[0],
        "one warning names the fallback")
big.GetPointData().GetScalars().Modified()
window.Render()
c.check(not mapper.GetLastFrameFellBack() and len(messages.errors) == 1,
        "changed scalars, memory back: object-order again")

# The reference integrator.
reference = hovr.vtkVolumeReferenceIntegrator()
messages = Messages(reference)
reference.SetInputData(big)
reference.SetVolumeProperty(prop)
reference.SetCamera(hio.default_camera(big.GetBounds(), parallel=True))
reference.SetImageSize(*SIZE)
limited(reference.Update)
print("reference:", messages.errors)
rgba = vtk_to_numpy(reference.GetOutput().GetPointData().GetScalars())
c.check(not messages.errors and rgba.shape == (SIZE[0] * SIZE[1], 4) and rgba[:, 3].max() > 0,
        "reference within the limit: no copy of the volume, the image is drawn")
del reference

# A second-order pre-integration table built on the CPU: 400^3 entries of float RGBA take
# 977 MiB.
table = hovr.vtkSecondOrderPreIntegrationTable()
messages = Messages(table)
array_messages = Messages(table.GetTable())  # vtkFloatArray's own report of the failure
table.SetVolumeProperty(prop)
table.SetScalarRange(0.0, 255.0)
table.SetSegmentLength(1.0)
table.SetTableSize(400)
table.SetChordSize(400)
table.SetDeviationSize(400)
built = limited(table.Update)
print("table:", messages.errors)
c.check(not built and len(messages.errors) == 1 and "Not enough memory" in messages.errors[0]
        and "64000000 entries" in messages.errors[0] and "977 MiB" in messages.errors[0]
        and table.GetTable().GetNumberOfTuples() == 0,
        "3D table out of memory: Update() is false, one error with the table's size, no table")
table.SetTableSize(32)
table.SetChordSize(32)
table.SetDeviationSize(32)
c.check(table.Update() and table.GetTable().GetNumberOfTuples() == 32 ** 3,
        "a smaller table then builds")
del table

# The analytic mapper's packed corners (uint8: 4 bytes per point, 243 MiB).
analytic = hovr.vtkAnalyticVolumeMapper()
analytic.SetBlendModeToIsoSurface()
analytic.SetInputData(big)
messages = Messages(analytic)
iso = vtkVolumeProperty()
iso.DeepCopy(prop)
iso.GetIsoSurfaceValues().SetValue(0, 100.5)
actor.SetMapper(analytic)
actor.SetProperty(iso)


def two_frames():
    window.Render()
    window.Render()
    return pixels()


unpacked = limited(two_frames)
print("analytic:", messages.errors, messages.warnings)
c.check(not messages.errors and len(messages.warnings) == 1 and
        "memory" in messages.warnings[0] and "same image" in messages.warnings[0] and
        analytic.GetCornerTextureMemorySize() == 0,
        "packed corners out of memory: one warning, no packed texture")
analytic.SetCornerPacking(False)
window.Render()
expected = pixels()
c.check(unpacked.max() > 0 and numpy.array_equal(unpacked, expected),
        "packed corners out of memory: the image of CornerPacking off")
analytic.SetCornerPacking(True)
big.GetPointData().GetScalars().Modified()
window.Render()
c.check(analytic.GetCornerTextureMemorySize() > 0 and len(messages.warnings) == 1 and
        numpy.array_equal(pixels(), expected),
        "changed scalars, memory back: packed again, same image")
window.Finalize()
c.finish()
