"""ScalarRange and WholeBounds: the range a mapper's tables span and the box its sampling grid is
anchored to besides its input's (a piece of a larger volume
drawn as the whole volume draws it, as the ParaView plugin does on every MPI rank).

Gaussian blobs (33^3) as float and as double (which VTK uploads rescaled to its range), the
spike transfer function, 64 x 64 float images, for first- and second-order pre-integration,
the adaptive ray, object-order ray casting and the analytic isosurface:
- unset (1, 0), or set to the input's own range, draws the same image, bit for bit;
- a wider range is spanned: pre-integration's table spans it exactly, and every method's image
  changes (its tables sample the transfer function elsewhere), except the isosurface, which
  reads no table: its image stays within float rounding (its raw-to-data mapping follows the
  range VTK draws its bricks with; a mismatch moves the surface and changes most pixels);
- unset again, the adaptive ray, object order and the isosurface draw their first image again,
  bit for bit; pre-integration treats a narrower range like a time step's (its measured sizes
  and their range stay while that range holds the data), so its table still holds the data.
WholeBounds on the adaptive ray and the adaptive 3D method: its own bounds draw the same
image, bit for bit; a box larger
by a third of a slice on every side moves its slices (the image changes, slightly); empty
bounds draw the first image again. The MPI test of the plugin checks the images of pieces
against one rank's whole volume.
"""

import math

import numpy

import hovr
from hovr import io as hio
from hovrtesting import Checker, FloatFrames, blobs, image_from_array, spike_property

c = Checker()
frames = FloatFrames((64, 64))

prop = spike_property()
prop.GetIsoSurfaceValues().SetValue(0, 104.0)
values = blobs(n=33)
volumes = {"float": image_from_array(values.astype(numpy.float32)),
           "double": image_from_array(values.astype(numpy.float64))}
camera = hio.default_camera(volumes["float"].GetBounds())


def draw(mapper, data):
    """The float image of one frame of ``mapper`` on ``data``, and its messages."""
    return frames.draw(mapper, data, prop, camera)


def preintegration(order):
    mapper = hovr.vtkPreIntegrationVolumeMapper()
    mapper.SetIntegration(order)
    mapper.SetSampleDistance(0.5)
    return mapper


def adaptive():
    mapper = hovr.vtkAdaptiveRayVolumeMapper()
    mapper.SetSampleDistance(0.5)
    mapper.SetOracleMode(hovr.vtkAdaptiveRayVolumeMapper.ORACLE_MINIMUM)
    return mapper


class ObjectOrder:
    """vtkObjectOrderVolumeMapper with ScalarRange on its caster, as the plugin sets it."""

    def __init__(self):
        self.mapper = hovr.vtkObjectOrderVolumeMapper()
        self.mapper.SetSampleDistance(0.5)

    def SetScalarRange(self, low, high):
        self.mapper.GetCaster().SetScalarRange(low, high)


def isosurface():
    mapper = hovr.vtkAnalyticVolumeMapper()
    mapper.SetBlendModeToIsoSurface()
    return mapper


def methods():
    yield "first order", preintegration(1), "float"
    yield "second order", preintegration(2), "float"
    yield "adaptive ray", adaptive(), "float"
    yield "object order", ObjectOrder(), "float"
    yield "isosurface", isosurface(), "float"
    yield "isosurface", isosurface(), "double"


def rms(a, b):
    return float(numpy.sqrt(numpy.mean((a - b) ** 2)))


for name, holder, kind in methods():
    mapper = getattr(holder, "mapper", holder)
    data = volumes[kind]
    low, high = data.GetPointData().GetScalars().GetRange()
    label = "%s (%s)" % (name, kind)
    camera.ParallelProjectionOn() if name == "object order" else camera.ParallelProjectionOff()
    first, messages = draw(mapper, data)
    c.check(first[..., 3].max() > 0.1 and not messages.errors and not messages.warnings,
            "%s draws the volume quietly (%s)" % (label, messages.errors + messages.warnings))
    holder.SetScalarRange(low, high)
    own, _ = draw(mapper, data)
    c.check(numpy.array_equal(own, first),
            "%s: its own range as ScalarRange draws the same image (max %.2e)"
            % (label, numpy.abs(own - first).max()))
    wide = (low - 2.0 * (high - low), high + (high - low))
    holder.SetScalarRange(*wide)
    widened, messages = draw(mapper, data)
    change = rms(widened, first)
    if name.startswith("isosurface"):
        c.check(change < 1e-3 and not messages.errors,
                "%s: a wider ScalarRange leaves the surface (RMS %.2e)" % (label, change))
    else:
        c.check(change > 0.0 and not messages.errors,
                "%s: a wider ScalarRange changes the tables' samples (RMS %.2e)"
                % (label, change))
    measured = name.endswith("order") and name != "object order"
    if measured:
        spanned = mapper.GetActiveTable().GetScalarRange()
        c.check(numpy.allclose(spanned, wide, rtol=0, atol=1e-9),
                "%s: the table spans the wider range %s (%s)" % (label, wide, spanned))
        # Like a time step's new range: the measured sizes and their range stay while that
        # range holds the data.
        for inside in ((low + 0.2 * (high - low), high - 0.2 * (high - low)),
                       (math.nan, math.nan), (1.0, 0.0)):
            holder.SetScalarRange(*inside)
            draw(mapper, data)
            spanned = mapper.GetActiveTable().GetScalarRange()
            c.check(spanned[0] <= low and spanned[1] >= high,
                    "%s: with ScalarRange %s the table holds the data's range (%s)"
                    % (label, inside, spanned))
    else:
        holder.SetScalarRange(1.0, 0.0)
        again, _ = draw(mapper, data)
        c.check(numpy.array_equal(again, first), "%s: unset again, the first image again (max "
                "%.2e)" % (label, numpy.abs(again - first).max()))

# WholeBounds: the adaptive methods' slices are anchored to the whole volume's box.
def pyramid():
    mapper = hovr.vtkAdaptiveSamplingVolumeMapper()
    mapper.SetSampleDistance(0.5)
    mapper.SetOracleModeToMinimum()
    return mapper


for name, make, parallel in (("adaptive ray", adaptive, False), ("adaptive 3D", pyramid, True)):
    mapper = make()
    data = volumes["float"]
    camera.SetParallelProjection(parallel)
    first, messages = draw(mapper, data)
    c.check(first[..., 3].max() > 0.1 and not messages.errors,
            "%s draws the volume (%s)" % (name, messages.errors))
    bounds = data.GetBounds()
    mapper.SetWholeBounds(bounds)
    own, _ = draw(mapper, data)
    c.check(numpy.array_equal(own, first), "%s: its own bounds as WholeBounds draw the same "
            "image (max %.2e)" % (name, numpy.abs(own - first).max()))
    # A whole box that reaches a third of a slice further on every side moves the slices: the
    # same volume, sampled elsewhere.
    spacing = mapper.GetSampleDistance() / 3.0
    mapper.SetWholeBounds([b + (spacing if k % 2 else -spacing) for k, b in enumerate(bounds)])
    moved, messages = draw(mapper, data)
    c.check(0.0 < rms(moved, first) < 0.01 and not messages.errors,
            "%s: a larger whole box moves the slices (RMS %.2e)" % (name, rms(moved, first)))
    mapper.SetWholeBounds(1.0, 0.0, 1.0, 0.0, 1.0, 0.0)
    again, _ = draw(mapper, data)
    c.check(numpy.array_equal(again, first), "%s: empty WholeBounds, the first image again "
            "(max %.2e)" % (name, numpy.abs(again - first).max()))

c.finish()
