"""Render a volume on the CPU with object-order ray casting, next to VTK's CPU ray caster.

hovr's vtkObjectOrderVolumeMapper replaces vtkFixedPointVolumeRayCastMapper in a plain VTK
pipeline (parallel projection, composite blending). It walks the volume front to back through
a min-max octree and skips what the transfer function hides and what is already behind opaque
pixels; the example prints the paper's counters and both mappers' error against
vtkVolumeReferenceIntegrator at the same sample distance, and writes the image.

    ./hovr python Examples/Python/object_order.py [--output image.png] [--size 400]
"""

import argparse
import math
import time

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkRenderer,
                                         vtkRenderWindow, vtkVolume, vtkVolumeProperty,
                                         vtkWindowToImageFilter)
from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL window factory)
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401

import hovr

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--output", default="object_order.png")
parser.add_argument("--size", type=int, default=400)
args = parser.parse_args()

# Marschner-Lobb, 64^3, with an opaque shell: most of the volume is hidden behind it.
source = hovr.vtkMarschnerLobbSource()
source.SetDimensions(64, 64, 64)
source.Update()
volume_data = source.GetOutput()

color = vtkColorTransferFunction()
color.AddRGBPoint(0.45, 0.55, 0.15, 0.10)
color.AddRGBPoint(0.55, 0.95, 0.75, 0.55)
color.AddRGBPoint(1.00, 1.00, 0.97, 0.90)
opacity = vtkPiecewiseFunction()
opacity.AddPoint(0.45, 0.0)
opacity.AddPoint(0.55, 1.0)
prop = vtkVolumeProperty()
prop.SetColor(color)
prop.SetScalarOpacity(opacity)
prop.SetScalarOpacityUnitDistance(0.05)
prop.SetInterpolationTypeToLinear()

window = vtkRenderWindow()
window.SetOffScreenRendering(1)
window.SetSize(args.size, args.size)
renderer = vtkRenderer()
window.AddRenderer(renderer)
camera = renderer.GetActiveCamera()
camera.SetPosition(3.0, -4.8, 2.7)
camera.SetFocalPoint(0.0, 0.0, 0.0)
camera.SetViewUp(0, 0, 1)
camera.ParallelProjectionOn()
camera.SetParallelScale(1.8)
step = 0.5 * volume_data.GetSpacing()[0]  # half a voxel


def draw(mapper):
    """Draw the volume with a mapper; the frame's RGBA (premultiplied, 0..1) and its time."""
    mapper.SetInputData(volume_data)
    mapper.SetSampleDistance(step)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    renderer.RemoveAllViewProps()
    renderer.AddVolume(volume)
    renderer.ResetCameraClippingRange()
    window.Render()  # first frame: octree and bricks
    start = time.perf_counter()
    window.Render()
    elapsed = 1000.0 * (time.perf_counter() - start)
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.SetInputBufferTypeToRGBA()
    grab.ReadFrontBufferOff()
    grab.Update()
    rgba = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()) / 255.0
    return rgba, elapsed, grab


fixed = vtkFixedPointVolumeRayCastMapper()
fixed.SetAutoAdjustSampleDistances(0)
fixed.SetLockSampleDistanceToInputSpacing(0)
fixed_rgba, fixed_ms, _ = draw(fixed)
mapper = hovr.vtkObjectOrderVolumeMapper()
rgba, ms, grab = draw(mapper)

reference = hovr.vtkVolumeReferenceIntegrator()
reference.SetInputData(volume_data)
reference.SetVolumeProperty(prop)
reference.SetCamera(camera)
reference.SetImageSize(args.size, args.size)
reference.Update()
exact = vtk_to_numpy(reference.GetOutput().GetPointData().GetScalars())


def rmse(image):
    return math.sqrt(float(((image - exact) ** 2).mean()))


caster = mapper.GetCaster()
in_view = caster.ComputeNonTransparentCells()
rendered = caster.GetNumberOfNonTransparentCells()
print("non-transparent cells: %d rendered of %d in view (%.1f%% hidden and skipped), "
      "octree nodes %d, samples %d" % (rendered, in_view, 100.0 * (1 - rendered / in_view),
                                       caster.GetNumberOfNodesVisited(),
                                       caster.GetNumberOfSamples()))
print("RMSE fixedpoint %.5f, object-order %.5f (8-bit window images); ms fixedpoint %.1f, "
      "object-order %.1f" % (rmse(fixed_rgba), rmse(rgba), fixed_ms, ms))
writer = vtkPNGWriter()
writer.SetFileName(args.output)
writer.SetInputConnection(grab.GetOutputPort())
writer.Write()
