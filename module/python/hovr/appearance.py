"""How a rendered volume looks: colour maps and opacity ramps over the data range, named
views, lighting.

Colour maps are ParaView colour presets (a JSON file, or a name from ParaView's own presets,
which ``./hovr setup`` exports to the file named by the environment variable
HOVR_PARAVIEW_PRESETS), rescaled to the data range as ParaView rescales them, in their
``ColorSpace``. Opacities are ramps or points in fractions of the data range.
"""

import math
import os

from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction

from .io import HovrError, camera_from_dict, read_json, set_color_space

# Named views: the view direction (ParaView's "+X" looks along +x) and the view up.
VIEWS = {"+x": ((1, 0, 0), (0, 0, 1)), "-x": ((-1, 0, 0), (0, 0, 1)),
         "+y": ((0, 1, 0), (0, 0, 1)), "-y": ((0, -1, 0), (0, 0, 1)),
         "+z": ((0, 0, 1), (0, 1, 0)), "-z": ((0, 0, -1), (0, 1, 0)),
         "iso": ((-1.0, 1.6, -0.9), (0, 0, 1))}

# Lighting of --shade: a white headlight, mostly diffuse, with a soft highlight.
SHADING = {"ambient": 0.25, "diffuse": 0.75, "specular": 0.25, "specular_power": 24.0}

# Opacity shorthands, as (fraction of the data range, opacity) points.
OPACITY_SHORTHANDS = {"ramp": [(0.0, 0.0), (1.0, 1.0)], "ramp-down": [(0.0, 1.0), (1.0, 0.0)]}


def paraview_presets():
    """ParaView's colour presets (a list of preset objects), exported by ``./hovr setup``."""
    path = os.environ.get("HOVR_PARAVIEW_PRESETS", "")
    if not path or not os.path.isfile(path):
        raise HovrError("colour maps by name come from ParaView's presets, which ./hovr setup "
                        "exports (HOVR_PARAVIEW_PRESETS=%s is not a file); give a preset JSON "
                        "file instead" % (path or "<unset>"))
    document = read_json(path, "ParaView presets")
    return document if isinstance(document, list) else [document]


def _find_preset(spec):
    if os.path.isfile(spec):
        document = read_json(spec, "colour map")
        presets = document if isinstance(document, list) else [document]
        for preset in presets:
            if isinstance(preset, dict) and preset.get("RGBPoints"):
                return preset, spec
        raise HovrError("%s holds no colour map (an object with 'RGBPoints')" % spec)
    presets = [p for p in paraview_presets() if isinstance(p, dict) and p.get("RGBPoints")]
    for preset in presets:
        if str(preset.get("Name", "")).lower() == spec.lower():
            return preset, spec
    close = [p["Name"] for p in presets if spec.lower() in str(p.get("Name", "")).lower()]
    raise HovrError("no colour map named %r%s (%d ParaView presets; a JSON file also works)"
                    % (spec, "; did you mean: " + ", ".join(close[:8]) if close else "",
                       len(presets)))


def colormap(spec, low, high):
    """A vtkColorTransferFunction from a ParaView colour preset (file or name), its points
    rescaled from their own range to [low, high], in the preset's colour space."""
    preset, origin = _find_preset(spec)
    rgb = preset["RGBPoints"]
    if (not isinstance(rgb, list) or len(rgb) < 4 or len(rgb) % 4
            or not all(isinstance(v, (int, float)) and math.isfinite(v) for v in rgb)):
        raise HovrError("%s: 'RGBPoints' must be a list of finite numbers, 4 per point" % origin)
    xs = rgb[0::4]
    x0, x1 = min(xs), max(xs)
    color = vtkColorTransferFunction()
    set_color_space(color, preset.get("ColorSpace", "RGB"), origin)
    color.SetClamping(1)
    for i in range(0, len(rgb), 4):
        fraction = (rgb[i] - x0) / (x1 - x0) if x1 > x0 else 0.0
        color.AddRGBPoint(low + fraction * (high - low), *rgb[i + 1:i + 4])
    return color


def grey_ramp(low, high, inverted=False):
    """Black at the lowest value to white at the highest (inverted: white to black, which
    shows a minimum intensity projection's minima bright)."""
    color = vtkColorTransferFunction()
    color.SetColorSpaceToRGB()
    color.SetClamping(1)
    color.AddRGBPoint(low, *((1.0, 1.0, 1.0) if inverted else (0.0, 0.0, 0.0)))
    color.AddRGBPoint(high, *((0.0, 0.0, 0.0) if inverted else (1.0, 1.0, 1.0)))
    return color


def opacity(spec, low, high):
    """A vtkPiecewiseFunction over [low, high] from ``ramp``, ``ramp-down``, ``flat:A``,
    points ``F:A,F:A,...`` (F a fraction of the data range, A an opacity) or a preset JSON
    file whose opacity ``Points`` are rescaled like a colour map's."""
    points = None
    origin = "--opacity %s" % spec
    if spec in OPACITY_SHORTHANDS:
        points = OPACITY_SHORTHANDS[spec]
    elif spec.startswith("flat:"):
        points = [(0.0, _number(spec[5:], origin)), (1.0, _number(spec[5:], origin))]
    elif os.path.isfile(spec):
        document = read_json(spec, "opacity")
        presets = document if isinstance(document, list) else [document]
        values = next((p["Points"] for p in presets if isinstance(p, dict) and p.get("Points")),
                      None)
        if (not isinstance(values, list) or len(values) < 4 or len(values) % 4
                or not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values)):
            raise HovrError("%s holds no opacity 'Points' [x, alpha, midpoint, sharpness, ...]"
                            % spec)
        xs = values[0::4]
        x0, x1 = min(xs), max(xs)
        points = [((x - x0) / (x1 - x0) if x1 > x0 else 0.0, a)
                  for x, a in zip(values[0::4], values[1::4])]
    elif ":" in spec:
        points = []
        for item in spec.split(","):
            parts = item.split(":")
            if len(parts) != 2:
                raise HovrError("%s: points are F:A pairs separated by commas" % origin)
            points.append((_number(parts[0], origin), _number(parts[1], origin)))
    else:
        raise HovrError("%s: use ramp, ramp-down, flat:A, F:A,F:A,... (fractions of the data "
                        "range) or a JSON file with opacity Points" % origin)
    function = vtkPiecewiseFunction()
    function.SetClamping(1)
    for fraction, alpha in points:
        if not 0.0 <= alpha <= 1.0:
            raise HovrError("%s: opacity %g is outside [0, 1]" % (origin, alpha))
        function.AddPoint(low + fraction * (high - low), alpha)
    return function


def _number(text, origin):
    try:
        value = float(text)
    except ValueError:
        raise HovrError("%s: %r is not a number" % (origin, text)) from None
    if not math.isfinite(value):
        raise HovrError("%s: %r is not finite" % (origin, text))
    return value


def named_camera(bounds, view="iso", zoom=1.0, azimuth=0.0, elevation=0.0, parallel=False,
                 angle=30.0):
    """A camera looking along a named view direction (VIEWS) at the centre of ``bounds``,
    framing their bounding sphere, then zoomed (> 1: closer) and turned about the focal point
    by ``azimuth`` and ``elevation`` degrees, as vtkCamera's Azimuth and Elevation turn it."""
    if view not in VIEWS:
        raise HovrError("unknown view %r (known: %s)" % (view, ", ".join(VIEWS)))
    if not (zoom > 0 and math.isfinite(zoom)):
        raise HovrError("the zoom must be positive, got %g" % zoom)
    direction, up = VIEWS[view]
    center = [(bounds[2 * a] + bounds[2 * a + 1]) / 2.0 for a in range(3)]
    radius = 0.5 * math.sqrt(sum((bounds[2 * a + 1] - bounds[2 * a]) ** 2 for a in range(3)))
    norm = math.sqrt(sum(d * d for d in direction))
    distance = radius / math.sin(math.radians(angle) / 2.0) * 1.02
    position = [c - distance * d / norm for c, d in zip(center, direction)]
    camera = camera_from_dict({"position": position, "focal_point": center, "view_up": list(up),
                               "view_angle": angle, "parallel_projection": bool(parallel),
                               "parallel_scale": radius * 1.02})
    camera.Azimuth(azimuth)
    camera.Elevation(elevation)
    camera.OrthogonalizeViewUp()
    camera.Dolly(zoom)
    if parallel:
        camera.SetParallelScale(camera.GetParallelScale() / zoom)
    return camera


def shade(prop):
    """Shading on, with SHADING's lighting."""
    prop.ShadeOn()
    prop.SetAmbient(SHADING["ambient"])
    prop.SetDiffuse(SHADING["diffuse"])
    prop.SetSpecular(SHADING["specular"])
    prop.SetSpecularPower(SHADING["specular_power"])
