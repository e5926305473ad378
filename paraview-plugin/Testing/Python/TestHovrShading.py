# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""pvbatch test of shaded first-order pre-integration in the hovr ParaView plugin.

Loads the plugin, volume renders the Marschner-Lobb source's 0.5 shell with the "hovr Volume"
representation in first order with Shade on, and checks that
  - Gradient Interpolation, Gooch Shading and Normal Array are there, with their documented
    defaults, entries and first-order-only panel visibility, and reach the mapper;
  - Shade reaches the volume property, the shaded image matches its baseline and differs from
    the unshaded one, and every frame is drawn by pre-integration (no fallback, no message);
  - each Gradient Interpolation value and Gooch shading change the image;
  - on the output of the Gradient Exaggeration filter, Normal Array offers ExaggeratedNormals
    and lighting with it changes the image, while its eps = 0 normals (central differences)
    light almost as the gradient does;
  - a Normal Array the input lacks is an error and nothing is drawn, and an empty name lights
    by the gradient again, as None does;
  - shaded second order is pre-integrated too and lit as first order; a positional light falls
    back to VTK's shader with a warning; the shaded first-order image is closer to VTK's
    shaded one than to the unshaded one.

    pvbatch TestHovrShading.py --plugin <hovr.so> --baseline <png> --output-dir <dir>

Without a baseline the test image is written to the output directory and the test fails: that
is how a baseline is made (inspect the image, then copy it to the baseline path).
"""
import argparse
import os
import re

from paraview.simple import (AddLight, ColorBy, GetColorTransferFunction,
                             GetOpacityTransferFunction, Hide, LoadPlugin, RemoveLight, Render,
                             Show)
from vtkmodules.vtkCommonCore import vtkLogger, vtkOutputWindow, vtkStringOutputWindow
# Python classes of VTK's GPU ray caster: hovr's mapper is seen as its nearest wrapped base.
from vtkmodules import vtkRenderingVolumeOpenGL2  # noqa: F401

from TestHovrPlugin import (Checker, capture, compare_with_baseline, image_difference,
                            mapper_setting, plain_view, read_rgb, run)

IMAGE_SIZE = [256, 256]
GRID_SPACING = 2.0 / 40.0  # Marschner-Lobb default: 41 points over [-1, 1]
# A fixed table size keeps the images independent of the mapper's measured sizes.
TABLE_SIZE = 256
# Renders of one scene repeat exactly within a run, so any difference between two settings is
# theirs; this floor asks for more than a few rounded pixels.
MIN_SETTING_DIFFERENCE = 0.5
# Shading must change the image by more than the baseline tolerance: the lit shell differs
# from the unlit one everywhere it faces away from the light.
MIN_SHADE_DIFFERENCE = 4.0
# The classes whose messages tell that a shaded frame was not drawn as asked.
SOURCES = ("vtkPreIntegrationVolumeMapper", "vtkExtensibleGPUVolumeRayCastMapper",
           "vtkOpenGLGPUVolumeRayCastMapper", "vtkGPUVolumeRayCastMapper",
           "vtkHovrVolumeRepresentation", "vtkPreIntegrationTable", "vtkVolumeShadingModel")


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", required=True, help="path of the hovr plugin (hovr.so)")
    parser.add_argument("--baseline", required=True, help="baseline PNG of the shaded image")
    parser.add_argument("--output-dir", required=True, help="where test images are written")
    return parser.parse_args()


class Captured:
    """What VTK and ParaView print (errors and warnings), collected instead of printed. In
    pvbatch Python's own output goes through the same window, so only frames are captured,
    not the checks' lines."""

    def __enter__(self):
        self.previous = vtkOutputWindow.GetInstance()
        self.previous.Register(None)
        self.window = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(self.window)
        self.verbosity = vtkLogger.GetCurrentVerbosityCutoff()
        vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
        return self

    def __exit__(self, *exc):
        vtkLogger.SetStderrVerbosity(self.verbosity)
        vtkOutputWindow.SetInstance(self.previous)
        self.previous.UnRegister(None)
        return False

    def messages(self):
        """The errors and warnings of the volume classes, one line each (a message is a
        block: "ERROR: In <file>, line <n>" and "<class> (<address>): ...")."""
        blocks = [" ".join(block.split()) for block in self.window.GetOutput().split("\n\n")]
        return [block for block in blocks
                if re.search(r"ERR|WARN|Error|Warning", block) and
                any(source in block for source in SOURCES)]


def frame(view, path):
    """Renders the view into path; returns path and the volume classes' messages meanwhile."""
    with Captured() as captured:
        capture(view, path)
    return path, captured.messages()


def mapper_string(mapper, name):
    """A string setting printed by the mapper's PrintSelf ("Name: value"), or None."""
    match = re.search(r"^\s*%s: (.*)$" % name, str(mapper), re.MULTILINE)
    return match.group(1) if match else None


def drawing_mapper(display):
    """The mapper that draws the display (pvbatch holds client and server in one process), or
    None before its first frame."""
    representation = display.GetClientSideObject().GetActiveRepresentation()
    return representation.GetActor().GetMapper()


def frames_drawn(display):
    """Frames the display's mapper drew with its extension (pre-integration), not VTK's."""
    mapper = drawing_mapper(display)
    return mapper_setting(mapper, "ExtensionFrameCount") if mapper else 0


def pre_integration_only(display, name):
    """Whether the property's panel hint shows it for the two pre-integration orders only."""
    hints = display.GetProperty(name).SMProperty.GetHints()
    values = set()
    stack = [hints] if hints else []
    while stack:
        element = stack.pop()
        if element.GetName() == "PropertyWidgetDecorator" and \
                element.GetAttribute("type") == "GenericDecorator" and \
                element.GetAttribute("mode") == "visibility" and \
                element.GetAttribute("property") == "HovrIntegration":
            values.add(element.GetAttribute("value"))
        stack.extend(element.GetNestedElement(i)
                     for i in range(element.GetNumberOfNestedElements()))
    return values == {"1", "2"}


def show_volume(source, view):
    display = Show(source, view)
    display.SetRepresentationType("hovr Volume")
    ColorBy(display, ("POINTS", "MarschnerLobb"))
    display.ScalarOpacityUnitDistance = GRID_SPACING
    display.HovrIntegration = "First-order pre-integration"
    display.HovrTableSize = TABLE_SIZE
    return display


def main():
    args = parse_arguments()
    os.makedirs(args.output_dir, exist_ok=True)
    checker = Checker()

    def image(name):
        return os.path.join(args.output_dir, "TestHovrShading-%s.png" % name)

    # ns= adds the plugin's creation functions (MarschnerLobb, GradientExaggeration) here.
    LoadPlugin(args.plugin, remote=False, ns=globals())
    if not checker.check("GradientExaggeration" in globals(),
                         "the plugin defines MarschnerLobb and GradientExaggeration"):
        return checker.failures
    source = globals()["MarschnerLobb"]()
    view = plain_view(IMAGE_SIZE)
    display = show_volume(source, view)

    checker.check(list(display.GetProperty("HovrGradientInterpolation").Available) ==
                  ["Constant", "Linear", "Non-linear"] and
                  display.HovrGradientInterpolation == "Non-linear",
                  "Gradient Interpolation: Constant, Linear, Non-linear, default Non-linear (%s)"
                  % display.HovrGradientInterpolation)
    checker.check(display.HovrGooch == 0, "Gooch Shading defaults to off (%s)" % display.HovrGooch)
    normal_arrays = list(display.GetProperty("HovrNormalArray").Available)
    checker.check(display.HovrNormalArray == "None" and normal_arrays == ["None"],
                  "Normal Array defaults to None, the only choice without 3-component point "
                  "arrays (%r of %s)" % (display.HovrNormalArray, normal_arrays))
    for name in ("HovrGradientInterpolation", "HovrGooch", "HovrNormalArray"):
        checker.check(pre_integration_only(display, name),
                      "%s is shown for first- and second-order pre-integration only" % name)

    # The Marschner-Lobb signal's 0.5 shell, a rippled surface whose normals turn quickly:
    # where the gradient interpolations differ.
    color = GetColorTransferFunction("MarschnerLobb")
    color.AutomaticRescaleRangeMode = "Never"
    color.ColorSpace = "RGB"
    color.RGBPoints = [0.0, 0.1, 0.3, 0.9,
                       0.5, 1.0, 0.55, 0.15,
                       1.0, 1.0, 1.0, 0.9]
    opacity = GetOpacityTransferFunction("MarschnerLobb")
    opacity.Points = [0.0, 0.0, 0.5, 0.0,
                      0.42, 0.0, 0.5, 0.0,
                      0.5, 0.9, 0.5, 0.0,
                      0.58, 0.0, 0.5, 0.0,
                      1.0, 0.0, 0.5, 0.0]
    # Show() and the first render reset the camera; fix it afterwards.
    Render(view)
    view.CameraPosition = [2.2, -3.6, 2.0]
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraViewAngle = 30.0

    unshaded, _ = frame(view, image("unshaded"))
    display.Shade = 1

    def shaded_frame(shown, name, what):
        """Renders a frame and checks that pre-integration drew the shown display without a
        message."""
        frames = frames_drawn(shown)
        path, said = frame(view, image(name))
        checker.check(not said and frames_drawn(shown) > frames,
                      "%s: drawn by pre-integration, no error or warning%s"
                      % (what, "".join("\n    " + m for m in said)))
        return path

    shaded = shaded_frame(display, "nonlinear", "shaded, non-linear")
    mapper = drawing_mapper(display)
    volume_property = display.GetClientSideObject().GetActiveRepresentation().GetActor() \
        .GetProperty()
    checker.check(volume_property.GetShade() == 1, "Shade reaches the volume property")
    compare_with_baseline(checker, shaded, args.baseline, "shaded first-order")
    difference = image_difference(shaded, unshaded)
    checker.check(difference >= MIN_SHADE_DIFFERENCE,
                  "shading changes the image: RMS difference %g, at least %g"
                  % (difference, MIN_SHADE_DIFFERENCE))

    images = {"Non-linear": shaded}
    for value, name in (("Linear", "linear"), ("Constant", "constant")):
        display.HovrGradientInterpolation = value
        images[value] = shaded_frame(display, name, "shaded, %s" % name)
    checker.check(mapper_setting(mapper, "GradientInterpolation") == 0,
                  "Gradient Interpolation reaches the mapper (%s)"
                  % mapper_setting(mapper, "GradientInterpolation"))
    for a, b in (("Constant", "Linear"), ("Linear", "Non-linear"), ("Constant", "Non-linear")):
        difference = image_difference(images[a], images[b])
        checker.check(difference > MIN_SETTING_DIFFERENCE,
                      "%s and %s gradient interpolation draw different images: RMS difference "
                      "%g, more than %g" % (a, b, difference, MIN_SETTING_DIFFERENCE))
    display.HovrGradientInterpolation = "Non-linear"

    display.HovrGooch = 1
    gooch = shaded_frame(display, "gooch", "Gooch shading")
    checker.check(mapper_setting(mapper, "Gooch") == 1, "Gooch Shading reaches the mapper")
    difference = image_difference(gooch, shaded)
    checker.check(difference > MIN_SETTING_DIFFERENCE,
                  "Gooch shading changes the image: RMS difference %g, more than %g"
                  % (difference, MIN_SETTING_DIFFERENCE))
    display.HovrGooch = 0

    # Shaded second order is pre-integrated too (its slab's two half arcs), with the same
    # lights: close to first order's image, far from the unlit one.
    # Its table is sized by measurement: a fixed 256^3 with eight moment layers would fill the
    # 3D texture's whole depth and 1 GiB.
    display.HovrIntegration = "Second-order pre-integration"
    display.HovrTableSize = 0
    second = shaded_frame(display, "second", "shaded second order")
    display.HovrTableSize = TABLE_SIZE
    to_first, to_unlit = image_difference(second, shaded), image_difference(second, unshaded)
    checker.check(to_first < 0.5 * to_unlit,
                  "shaded second order is lit as first order: RMS difference %g, less than half "
                  "of its difference to the unshaded image %g" % (to_first, to_unlit))
    # VTK's shader lights the same normals (its gradient) with the same lights and point
    # sampling: a wrong sign or lighting convention would leave the pre-integrated image no
    # closer to it than the unlit one.
    display.HovrIntegration = "Stock"
    stock, _ = frame(view, image("stock"))
    to_stock, to_unshaded = image_difference(shaded, stock), image_difference(shaded, unshaded)
    checker.check(to_stock < to_unshaded,
                  "the shaded image is closer to VTK's shaded one than to the unshaded one: "
                  "RMS difference %g < %g" % (to_stock, to_unshaded))
    display.HovrIntegration = "First-order pre-integration"
    light = AddLight(view=view)
    light.Type = "Positional"
    positional, said = frame(view, image("positional"))
    checker.check(any("positional light" in m for m in said) and
                  read_rgb(positional)[0].max() > 0,
                  "a positional light falls back with a warning (%s)" % said)
    RemoveLight(light)

    # Normals from the Gradient Exaggeration filter, on the filter's output.
    exaggeration = globals()["GradientExaggeration"](Input=source)
    Hide(source, view)
    filtered = show_volume(exaggeration, view)
    filtered.Shade = 1
    normal_arrays = list(filtered.GetProperty("HovrNormalArray").Available)
    checker.check(normal_arrays == ["ExaggeratedNormals", "None"] and
                  filtered.HovrNormalArray == "None",
                  "the filter's output offers ExaggeratedNormals and None, default None (%r of "
                  "%s)" % (filtered.HovrNormalArray, normal_arrays))
    gradient = shaded_frame(filtered, "gradient", "the filter's output lit by the gradient")
    filtered.HovrNormalArray = "ExaggeratedNormals"
    exaggerated = shaded_frame(filtered, "exaggerated", "lit by ExaggeratedNormals")
    mapper = drawing_mapper(filtered)
    checker.check(mapper_string(mapper, "NormalArrayName") == "ExaggeratedNormals",
                  "Normal Array reaches the mapper (%s)" % mapper_string(mapper, "NormalArrayName"))
    exaggerated_difference = image_difference(exaggerated, gradient)
    checker.check(exaggerated_difference > MIN_SHADE_DIFFERENCE,
                  "exaggerated normals change the image: RMS difference %g, more than %g"
                  % (exaggerated_difference, MIN_SHADE_DIFFERENCE))
    # eps = 0 gives the normalised central differences at the grid points: interpolated, they
    # differ from the gradient taken at each sample only between grid points, so the image
    # stays far closer to the gradient's than the exaggerated one (normals read in the wrong
    # order or sign would light the shell as differently as that).
    exaggeration.Epsilon = 0.0
    plain = shaded_frame(filtered, "plain-normals", "lit by the eps = 0 normals")
    plain_difference = image_difference(plain, gradient)
    checker.check(plain_difference < 0.5 * exaggerated_difference,
                  "the eps = 0 normals light almost as the gradient: RMS difference %g, less "
                  "than half of the exaggerated normals' %g"
                  % (plain_difference, exaggerated_difference))
    exaggeration.Epsilon = 1.0

    filtered.HovrNormalArray = "NoSuchArray"
    missing, said = frame(view, image("missing"))
    checker.check(any("NoSuchArray" in m and "not drawing" in m for m in said),
                  "a Normal Array the input lacks is an error (%s)" % said)
    checker.check(read_rgb(missing)[0].max() == 0, "a Normal Array the input lacks draws nothing")
    filtered.HovrNormalArray = ""
    empty = shaded_frame(filtered, "empty-name", "an empty Normal Array")
    difference = image_difference(empty, gradient)
    checker.check(difference == 0.0, "an empty Normal Array lights by the gradient, as None "
                  "does: RMS difference %g" % difference)
    return checker.failures


if __name__ == "__main__":
    run(main)
