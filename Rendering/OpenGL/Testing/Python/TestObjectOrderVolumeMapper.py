"""vtkObjectOrderVolumeMapper in a render window: what it draws is vtkObjectOrderRayCaster's
image (exactly: a float texture drawn texel for pixel, only over the volume's pixels); a volume moved by its matrix with the camera moved alike
gives the same image; what it cannot draw (a perspective camera, maximum intensity, cropping)
is drawn by vtkFixedPointVolumeRayCastMapper after one warning per reason, and drawing
returns to the object-order caster when the reason goes away; the array the scalar mode and
SelectScalarArray choose is the one drawn, and cell data is an error with nothing drawn.
"""

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkRenderingCore import vtkVolume

import hovr
from hovr import io as hio
from hovr import methods as hm
from hovrtesting import Checker, Messages, marschner_lobb_scene, offscreen_window

c = Checker()
SIZE = (96, 80)
scene = marschner_lobb_scene(SIZE)
scene = hm.Scene(scene.image, scene.prop, hio.default_camera(scene.image.GetBounds(),
                                                             parallel=True), SIZE)
step = 0.025


def caster_pixels(camera, matrix=None):
    caster = hovr.vtkObjectOrderRayCaster()
    caster.SetInputData(scene.image)
    caster.SetVolumeProperty(scene.prop)
    caster.SetCamera(camera)
    caster.SetImageSize(*SIZE)
    caster.SetSampleDistance(step)
    caster.SetVolumeMatrix(matrix)
    caster.Update()
    return vtk_to_numpy(caster.GetOutput().GetPointData().GetScalars()).copy()


renderer = hm.Renderer()
drawn = renderer.render("objectorder", scene, step / 0.05)
window = vtk_to_numpy(drawn.image.GetPointData().GetScalars())
computed = caster_pixels(scene.camera)
difference = numpy.abs(window - computed).max()
print("window against caster: max difference %.2e, alpha max %.3f" % (difference,
                                                                   computed[:, 3].max()))
c.check(computed[:, 3].max() > 0.3 and difference < 1e-6,
        "the window shows the caster's image (difference %.1e)" % difference)
c.check(drawn.samples_per_frame > 0 and drawn.extra["nontransparent_cells"] > 0,
        "the mapper reports the caster's counters")
# Rays stopped at their first opacity render no more cells than rays stopped when opaque.
c.check(drawn.extra["occluded_ratio_first_hit"] >= drawn.extra["occluded_ratio"] > 0.0,
        "the first-hit occluded ratio bounds the occluded ratio (%.3f >= %.3f)"
        % (drawn.extra["occluded_ratio_first_hit"], drawn.extra["occluded_ratio"]))

# Zoomed out and off centre: the mapper draws only the volume's pixels, at their place.
small = hio.default_camera(scene.image.GetBounds(), parallel=True)
small.SetParallelScale(2.5 * small.GetParallelScale())
shift = [0.9 * small.GetParallelScale() * u for u in small.GetViewUp()]
small.SetPosition(*[p + d for p, d in zip(small.GetPosition(), shift)])
small.SetFocalPoint(*[p + d for p, d in zip(small.GetFocalPoint(), shift)])
corner = renderer.render("objectorder", hm.Scene(scene.image, scene.prop, small, SIZE),
                         step / 0.05)
window = vtk_to_numpy(corner.image.GetPointData().GetScalars())
computed_small = caster_pixels(small)
lit = numpy.nonzero(computed_small[:, 3].reshape(SIZE[1], SIZE[0]))
difference = numpy.abs(window - computed_small).max()
c.check(lit[0].size > 0 and lit[0].max() < SIZE[1] // 2 and difference < 1e-6,
        "a small volume in the image's lower half: the window shows the caster's image "
        "(difference %.1e)" % difference)

# Moving the volume by its matrix and the camera alike changes nothing.
moved = hio.default_camera(scene.image.GetBounds(), parallel=True)
moved.SetPosition(*[p + d for p, d in zip(moved.GetPosition(), (0.3, -0.2, 0.1))])
moved.SetFocalPoint(*[p + d for p, d in zip(moved.GetFocalPoint(), (0.3, -0.2, 0.1))])
volume = vtkVolume()
volume.SetPosition(0.3, -0.2, 0.1)
shifted = caster_pixels(moved, volume.GetMatrix())
c.check(numpy.abs(shifted - computed).max() < 1e-5,
        "a volume moved with the camera gives the same image (%.1e)"
        % numpy.abs(shifted - computed).max())

# Fallbacks, drawn directly in a window.
window, view = offscreen_window(SIZE)
mapper = hovr.vtkObjectOrderVolumeMapper()
mapper.SetInputData(scene.image)
mapper.SetSampleDistance(step)
messages = Messages(mapper)
volume = vtkVolume()
volume.SetMapper(mapper)
volume.SetProperty(scene.prop)
view.AddVolume(volume)
view.GetActiveCamera().DeepCopy(scene.camera)
view.ResetCameraClippingRange()
window.Render()
c.check(not mapper.GetLastFrameFellBack() and not messages.warnings,
        "parallel composite: drawn by the object-order caster")
cases = [("parallel", lambda on: view.GetActiveCamera().SetParallelProjection(not on)),
         ("composite", lambda on: mapper.SetBlendMode(1 if on else 0)),
         ("crop", lambda on: mapper.SetCropping(on))]
for reason, toggle in cases:
    toggle(True)
    window.Render()
    window.Render()  # warned once
    fell_back = mapper.GetLastFrameFellBack()
    warned = [w for w in messages.warnings if reason in w]
    c.check(fell_back and len(warned) == 1,
            "%s: drawn by vtkFixedPointVolumeRayCastMapper after one warning (%d)" % (
                reason, len(warned)))
    toggle(False)
    window.Render()
    c.check(not mapper.GetLastFrameFellBack(), "%s undone: object-order again" % reason)
# The array the scalar mode and SelectScalarArray choose is the one drawn: a second point
# array, selected by name, gives the image of that array made active; cell data is an error.
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk  # noqa: E402
two = vtkImageData()
two.DeepCopy(scene.image)
flipped = numpy_to_vtk(1.0 - vtk_to_numpy(two.GetPointData().GetScalars()), deep=1)
flipped.SetName("flipped")
two.GetPointData().AddArray(flipped)
mapper.SetInputData(two)
mapper.SetScalarModeToUsePointFieldData()
mapper.SelectScalarArray("flipped")
window.Render()
c.check(not mapper.GetLastFrameFellBack(), "a selected point array: drawn by the caster")
selected = vtk_to_numpy(mapper.GetCaster().GetOutput().GetPointData().GetScalars()).copy()
active = vtkImageData()
active.DeepCopy(scene.image)
active.GetPointData().SetScalars(flipped)
mapper.SetInputData(active)
mapper.SetScalarModeToDefault()
window.Render()
made_active = vtk_to_numpy(mapper.GetCaster().GetOutput().GetPointData().GetScalars())
c.check(numpy.array_equal(selected, made_active) and not numpy.array_equal(selected, computed),
        "the selected array is the one drawn")
c.check(not messages.errors, "no errors")
mapper.SetScalarModeToUseCellData()
window.Render()
c.check(len(messages.errors) == 1 and "point scalars" in messages.errors[0],
        "cell data: an error, nothing drawn (VTK's CPU mapper does not draw it either)")
mapper.SetScalarModeToDefault()
# A frame the caster fails (a negative step: an error, nothing drawn) still fires a render
# end event after its start event.
from vtkmodules.vtkCommonCore import vtkCommand  # noqa: E402
events = []
mapper.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, lambda o, e: events.append("start"))
mapper.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, lambda o, e: events.append("end"))
errors = len(messages.errors)
mapper.SetSampleDistance(-1.0)
window.Render()
c.check(len(messages.errors) == errors + 1 and "sample distance" in messages.errors[-1]
        and events == ["start", "end"], "a negative step: the caster's error, start and end "
        "events paired (%s)" % events)
mapper.SetSampleDistance(step)


def window_rgba():
    window.Render()
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.SetInputBufferTypeToRGBA()
    grab.Update()
    return vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()).astype(int)


# A piece with ghost points (the caster's OwnedExtent) in perspective: VTK's mapper draws the
# owned points alone, the image of the piece without its ghost points.
from hovrtesting import cut_pieces  # noqa: E402
(owned, ghosted), = cut_pieces(scene.image, 0, 2, 3)[:1]
(_, plain), = cut_pieces(scene.image, 0, 2)[:1]
view.GetActiveCamera().SetParallelProjection(False)
mapper.SetInputData(plain)
expected = window_rgba()
mapper.SetInputData(ghosted)
mapper.GetCaster().SetOwnedExtent(owned)
drawn = window_rgba()
mapper.GetCaster().SetOwnedExtent(0, -1, 0, -1, 0, -1)
whole_piece = window_rgba()
c.check(mapper.GetLastFrameFellBack() and numpy.array_equal(drawn, expected)
        and not numpy.array_equal(whole_piece, expected), "perspective, a piece with ghost "
        "points: VTK's mapper draws its owned points alone (%d pixels differ with the ghost "
        "points)" % numpy.count_nonzero(numpy.any(whole_piece != expected, axis=1)))
window.Finalize()
renderer.close()
c.finish()
