# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""pvbatch test of adaptive sampling in the hovr ParaView plugin.

Loads the plugin, volume renders the Blobs source (Gaussian blobs in empty space) with the
"hovr Volume" representation and checks that
  - the two adaptive methods are Rendering Method entries, and Maximum Level, Oracle and
    Oracle Epsilon are there with their documented defaults, shown for those methods only;
  - adaptive sampling along rays draws with its own shader (no fallback, no message) in the
    default perspective view, close to first-order pre-integration at the same sample
    distance, and the settings reach its mapper; the "Minimum" oracle (full rate) is closer
    still, and the "Maximum" oracle (longest steps everywhere) draws a different image;
  - an opacity edit reaches the oracle: the adaptive image follows pre-integration's new one;
  - the pyramid refuses a perspective camera with an error and draws nothing, and with a
    parallel projection draws the blobs close to pre-integration's parallel image.

    pvbatch TestHovrAdaptive.py --plugin <hovr.so> --output-dir <dir>
"""
import argparse
import os

from paraview.simple import (ColorBy, GetColorTransferFunction, GetOpacityTransferFunction,
                             LoadPlugin, Render, SaveScreenshot, Show)
from vtkmodules import vtkRenderingVolumeOpenGL2  # noqa: F401

from TestHovrPlugin import Checker, image_difference, mapper_setting, plain_view, read_rgb, run
from TestHovrShading import Captured, drawing_mapper, frames_drawn

IMAGE_SIZE = [256, 256]
# RMS differences (0-255 RGB) that count as "close": the adaptive image against
# pre-integration at the same sample distance, where skipping only empty space changes
# nothing but the samples' positions on the global slice grid.
CLOSE = 2.0
# A setting that must change the image changes it by more than this.
DIFFERENT = 0.5
SOURCES = ("vtkAdaptiveRayVolumeMapper", "vtkAdaptiveSamplingVolumeMapper",
           "vtkAdaptiveSamplingOracle", "vtkExtensibleGPUVolumeRayCastMapper",
           "vtkOpenGLGPUVolumeRayCastMapper", "vtkHovrVolumeRepresentation",
           "vtkPreIntegrationVolumeMapper")


class Messages(Captured):
    def messages(self):
        blocks = [" ".join(block.split()) for block in self.window.GetOutput().split("\n\n")]
        return [block for block in blocks if ("ERR" in block or "WARN" in block or
                                              "Error" in block or "Warning" in block)
                and any(source in block for source in SOURCES)]


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", required=True, help="path of the hovr plugin (hovr.so)")
    parser.add_argument("--output-dir", required=True, help="where test images are written")
    return parser.parse_args()


def shown_for_adaptive(display, name):
    """Whether the property's panel hint shows it for the two adaptive methods only."""
    hints = display.GetProperty(name).SMProperty.GetHints()
    values = set()
    stack = [hints] if hints else []
    while stack:
        element = stack.pop()
        if element.GetName() == "PropertyWidgetDecorator" and \
                element.GetAttribute("property") == "HovrIntegration":
            values.add(element.GetAttribute("value"))
        stack.extend(element.GetNestedElement(i) for i in range(element.GetNumberOfNestedElements()))
    return values == {"7", "8"}


def main():
    args = parse_arguments()
    os.makedirs(args.output_dir, exist_ok=True)
    checker = Checker()

    def frame(name):
        path = os.path.join(args.output_dir, "TestHovrAdaptive-%s.png" % name)
        with Messages() as captured:
            Render(view)
            SaveScreenshot(path, view, ImageResolution=IMAGE_SIZE, TransparentBackground=0)
        return path, captured.messages()

    LoadPlugin(args.plugin, remote=False, ns=globals())
    if not checker.check("Blobs" in globals(), "the plugin defines the Blobs source"):
        return checker.failures
    source = globals()["Blobs"]()
    source.Dimensions = [65, 65, 65]
    view = plain_view(IMAGE_SIZE)
    display = Show(source, view)
    display.SetRepresentationType("hovr Volume")
    ColorBy(display, ("POINTS", "Blobs"))
    display.ScalarOpacityUnitDistance = 2.0 / 64
    display.HovrSampleDistance = 1.0 / 64  # half a voxel
    color = GetColorTransferFunction("Blobs")
    color.AutomaticRescaleRangeMode = "Never"
    color.RGBPoints = [0.05, 0.2, 0.35, 0.8, 0.4, 0.9, 0.6, 0.3, 1.0, 1.0, 0.95, 0.85]
    opacity = GetOpacityTransferFunction("Blobs")
    opacity.Points = [0.05, 0.0, 0.5, 0.0, 0.4, 0.3, 0.5, 0.0, 0.55, 0.05, 0.5, 0.0,
                      0.75, 0.8, 0.5, 0.0, 1.0, 0.9, 0.5, 0.0]

    methods = list(display.GetProperty("HovrIntegration").Available)
    checker.check("Adaptive sampling along rays" in methods and
                  "Adaptive sampling in 3D (pyramid)" in methods,
                  "the adaptive methods are Rendering Method entries (%s)" % methods)
    checker.check(display.HovrMaximumLevel == 3 and display.HovrOracleMode == "Opacity range"
                  and abs(display.HovrOracleEpsilon - 0.002) < 1e-12,
                  "defaults: Maximum Level 3, Oracle 'Opacity range', Epsilon 0.002 (%s, %s, %s)"
                  % (display.HovrMaximumLevel, display.HovrOracleMode,
                     display.HovrOracleEpsilon))
    for name in ("HovrMaximumLevel", "HovrOracleMode", "HovrOracleEpsilon"):
        checker.check(shown_for_adaptive(display, name),
                      "%s is shown for the adaptive methods only" % name)

    display.HovrIntegration = "First-order pre-integration"
    Render(view)
    view.CameraPosition = [2.4, -3.8, 2.1]
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraViewAngle = 30.0
    preint, said = frame("preint1")
    checker.check(not said and read_rgb(preint)[0].max() > 50, "pre-integration draws the blobs")

    display.HovrIntegration = "Adaptive sampling along rays"
    adaptive, said = frame("adaptive-ray")
    mapper = drawing_mapper(display)
    name = mapper.GetClassName() if mapper else None
    checker.check(name == "vtkAdaptiveRayVolumeMapper",
                  "along rays draws with vtkAdaptiveRayVolumeMapper (%s)" % name)
    frames = frames_drawn(display)
    checker.check(not said and frames > 0, "along rays: drawn by its shader, no message%s"
                  % "".join("\n    " + m for m in said))
    ray_difference = image_difference(adaptive, preint)
    checker.check(ray_difference < CLOSE, "along rays is close to pre-integration at the same "
                  "sample distance: RMS difference %g, less than %g" % (ray_difference, CLOSE))
    display.HovrMaximumLevel = 2
    frame("adaptive-ray-l2")
    checker.check(mapper_setting(drawing_mapper(display), "MaximumLevel") == 2,
                  "Maximum Level reaches the mapper")
    display.HovrMaximumLevel = 3

    display.HovrOracleMode = "Minimum (full rate)"
    full, said = frame("adaptive-ray-min")
    full_difference = image_difference(full, preint)
    checker.check(not said and full_difference <= ray_difference + 1e-9,
                  "the Minimum oracle (full rate) is at least as close: %g" % full_difference)
    display.HovrOracleMode = "Maximum"
    longest, said = frame("adaptive-ray-max")
    checker.check(not said and image_difference(longest, adaptive) > DIFFERENT,
                  "the Maximum oracle draws a different image: RMS difference %g"
                  % image_difference(longest, adaptive))
    display.HovrOracleMode = "Opacity range"

    # An opacity edit: the oracle's features move with it.
    opacity.Points = [0.05, 0.0, 0.5, 0.0, 0.2, 0.6, 0.5, 0.0, 0.3, 0.0, 0.5, 0.0,
                      1.0, 0.0, 0.5, 0.0]
    edited, said = frame("adaptive-ray-edited")
    display.HovrIntegration = "First-order pre-integration"
    edited_preint, _ = frame("preint1-edited")
    edited_difference = image_difference(edited, edited_preint)
    checker.check(not said and image_difference(edited, adaptive) > DIFFERENT and
                  edited_difference < CLOSE,
                  "after an opacity edit along rays follows pre-integration: RMS difference %g"
                  % edited_difference)
    opacity.Points = [0.05, 0.0, 0.5, 0.0, 0.4, 0.3, 0.5, 0.0, 0.55, 0.05, 0.5, 0.0,
                      0.75, 0.8, 0.5, 0.0, 1.0, 0.9, 0.5, 0.0]

    # The pyramid: perspective refused, parallel drawn.
    display.HovrIntegration = "Adaptive sampling in 3D (pyramid)"
    refused, said = frame("pyramid-perspective")
    checker.check(any("arallel" in m for m in said) and read_rgb(refused)[0].max() == 0,
                  "the pyramid refuses a perspective camera with an error and draws nothing "
                  "(%s)" % said)
    view.CameraParallelProjection = 1
    pyramid, said = frame("pyramid")
    display.HovrIntegration = "First-order pre-integration"
    parallel, _ = frame("preint1-parallel")
    pyramid_difference = image_difference(pyramid, parallel)
    checker.check(not said and read_rgb(pyramid)[0].max() > 50 and pyramid_difference < CLOSE,
                  "with a parallel projection the pyramid draws the blobs, close to "
                  "pre-integration: RMS difference %g%s"
                  % (pyramid_difference, "".join("\n    " + m for m in said)))
    return checker.failures


if __name__ == "__main__":
    run(main)
