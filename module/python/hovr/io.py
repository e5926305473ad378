"""Reading volumes, transfer functions and cameras; writing images.

Everything ``hovr render`` and ``hovr bench`` read from disk goes through here, and every
problem with an input becomes a :class:`HovrError` with a message a user can act on.
"""

import json
import math
import os

from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkCamera, vtkColorTransferFunction, vtkVolumeProperty

# The scalar types of raw input and their VTK names.
RAW_TYPES = {
    "uint8": "UnsignedChar",
    "uint16": "UnsignedShort",
    "int16": "Short",
    "float32": "Float",
}


class HovrError(Exception):
    """A user-facing error: bad input, impossible settings."""


# ParaView's ColorSpace names and vtkColorTransferFunction's.
COLOR_SPACES = {"RGB": "RGB", "HSV": "HSV", "Lab": "Lab", "Lab/CIEDE2000": "LabCIEDE2000",
                "CIELAB": "Lab", "Diverging": "Diverging", "Step": "Step"}


def set_color_space(color, name, origin="preset"):
    """Set a vtkColorTransferFunction's colour space from ParaView's ColorSpace name."""
    vtk_name = COLOR_SPACES.get(name)
    if vtk_name is None:
        raise HovrError("%s: unknown ColorSpace %r (known: %s)" % (origin, name,
                                                                   ", ".join(COLOR_SPACES)))
    getattr(color, "SetColorSpaceTo" + vtk_name)()


class _ErrorCatcher:
    """Collects the error messages a VTK object emits, instead of printing them."""

    def __init__(self, obj):
        self.messages = []
        self._obj = obj
        self._tags = [obj.AddObserver(vtkCommand.ErrorEvent, self._on_error),
                      obj.AddObserver(vtkCommand.WarningEvent, self._on_warning)]

    def _on_error(self, _obj, _event, message=None):
        self.messages.append(str(message).strip() if message else "unknown error")

    _on_error.CallDataType = "string0"

    def _on_warning(self, _obj, _event, message=None):
        pass

    _on_warning.CallDataType = "string0"

    def detach(self):
        for tag in self._tags:
            self._obj.RemoveObserver(tag)


class _VTKOutputCaptured:
    """Within ``with``: what VTK objects without an observer report (the XML parser inside a
    reader, for one) goes to a string instead of the terminal, where VTK's logger would print
    it with colour codes; ``text`` holds it after."""

    def __enter__(self):
        from vtkmodules.vtkCommonCore import vtkLogger, vtkOutputWindow, vtkStringOutputWindow
        self._previous = vtkOutputWindow.GetInstance()
        self._previous.Register(None)  # kept alive while replaced
        self._window = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(self._window)
        self._verbosity = vtkLogger.GetCurrentVerbosityCutoff()
        vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
        return self

    def __exit__(self, *exc):
        from vtkmodules.vtkCommonCore import vtkLogger, vtkOutputWindow
        self.text = self._window.GetOutput()
        vtkLogger.SetStderrVerbosity(self._verbosity)
        vtkOutputWindow.SetInstance(self._previous)
        self._previous.UnRegister(None)
        return False


def _run_reader(reader, path):
    catcher = _ErrorCatcher(reader)
    executive = reader.GetExecutive()
    catcher_exec = _ErrorCatcher(executive)
    try:
        with _VTKOutputCaptured():
            reader.Update()
    finally:
        catcher.detach()
        catcher_exec.detach()
    messages = catcher.messages + catcher_exec.messages
    if messages:
        raise HovrError("cannot read %s: %s" % (path, messages[0].splitlines()[-1]))
    return reader.GetOutputDataObject(0)


# Extensions of the formats whose files describe themselves (no --dims, --type, --spacing).
SELF_DESCRIBING = (".vti", ".mhd", ".mha", ".nii", ".nii.gz", ".slc", ".vtk")


def read_volume(path, dims=None, scalar_type=None, spacing=None, header_bytes=None):
    """Read a scalar volume as vtkImageData.

    Formats: .vti, .mhd/.mha, .nii/.nii.gz, .slc, legacy .vtk structured points, and raw
    little-endian data (``dims`` and ``scalar_type`` required) laid out as numpy and ParaView
    read it: x fastest, then rows in increasing y, then slices in increasing z, after
    ``header_bytes`` bytes (default 0; the file must hold exactly the header and the data).
    """
    if not os.path.isfile(path):
        raise HovrError("input file not found: %s" % path)
    if not os.access(path, os.R_OK):
        raise HovrError("input file is not readable: %s" % path)
    lower = path.lower()
    raw_options = [name for name, value in (("--dims", dims), ("--type", scalar_type),
                                            ("--spacing", spacing),
                                            ("--header-bytes", header_bytes))
                   if value is not None]
    if lower.endswith(SELF_DESCRIBING):
        if raw_options:
            raise HovrError("%s applies to raw input only: %s is a %s file, which gives its "
                            "own dimensions, type and spacing" % (
                                " and ".join(raw_options), path,
                                next(e for e in SELF_DESCRIBING if lower.endswith(e))))
    elif raw_options or lower.endswith(".raw"):
        return _read_raw(path, dims, scalar_type, spacing, header_bytes)
    if lower.endswith(".vti"):
        from vtkmodules.vtkIOXML import vtkXMLImageDataReader
        reader = vtkXMLImageDataReader()
    elif lower.endswith(".mhd") or lower.endswith(".mha"):
        from vtkmodules.vtkIOImage import vtkMetaImageReader
        reader = vtkMetaImageReader()
    elif lower.endswith(".nii") or lower.endswith(".nii.gz"):
        from vtkmodules.vtkIOImage import vtkNIFTIImageReader
        reader = vtkNIFTIImageReader()
    elif lower.endswith(".slc"):
        from vtkmodules.vtkIOImage import vtkSLCReader
        reader = vtkSLCReader()
    elif lower.endswith(".vtk"):
        from vtkmodules.vtkIOLegacy import vtkDataSetReader
        reader = vtkDataSetReader()
    else:
        raise HovrError("unknown volume format of %s (use .vti, .mhd, .nii, .nii.gz, .slc, "
                        ".vtk, or raw with --dims and --type)" % path)
    reader.SetFileName(path)
    data = _run_reader(reader, path)
    if not isinstance(data, vtkImageData):
        raise HovrError("%s holds a %s, not image data (structured points)"
                        % (path, data.GetClassName() if data else "nothing"))
    image = vtkImageData()
    image.ShallowCopy(data)
    if image.GetNumberOfPoints() == 0:
        raise HovrError("%s holds an empty volume" % path)
    return image


def _read_raw(path, dims, scalar_type, spacing, header_bytes=None):
    if dims is None or scalar_type is None:
        raise HovrError("raw input %s needs --dims X Y Z and --type %s"
                        % (path, "|".join(RAW_TYPES)))
    if scalar_type not in RAW_TYPES:
        raise HovrError("unknown raw type %r (use %s)" % (scalar_type, ", ".join(RAW_TYPES)))
    dims = [int(d) for d in dims]
    if len(dims) != 3 or min(dims) < 1:
        raise HovrError("--dims needs three positive sizes, got %s" % dims)
    spacing = [float(s) for s in (spacing or (1.0, 1.0, 1.0))]
    if len(spacing) != 3 or not all(s > 0 and math.isfinite(s) for s in spacing):
        raise HovrError("--spacing needs three positive numbers, got %s" % spacing)
    header = 0 if header_bytes is None else int(header_bytes)
    if header < 0:
        raise HovrError("--header-bytes must not be negative, got %d" % header)
    size = os.path.getsize(path)
    bytes_per = {"uint8": 1, "uint16": 2, "int16": 2, "float32": 4}[scalar_type]
    expected = dims[0] * dims[1] * dims[2] * bytes_per
    if size != header + expected:
        # A larger file is no guess at a header: its layout is not what the user said.
        raise HovrError(
            "%s has %d bytes, but %dx%dx%d %s needs %d%s; check --dims and --type%s"
            % (path, size, dims[0], dims[1], dims[2], scalar_type, expected,
               " after a %d-byte header" % header if header else "",
               ", or give --header-bytes %d if the file starts with a header"
               % (size - expected) if size > expected and not header else ""))
    from vtkmodules.vtkIOImage import vtkImageReader2
    reader = vtkImageReader2()
    reader.SetFileName(path)
    reader.SetFileDimensionality(3)
    reader.SetDataExtent(0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1)
    reader.SetDataSpacing(spacing)
    reader.SetDataByteOrderToLittleEndian()
    getattr(reader, "SetDataScalarTypeTo" + RAW_TYPES[scalar_type])()
    reader.SetNumberOfScalarComponents(1)
    reader.SetHeaderSize(header)
    # Rows in increasing y, as numpy writes them and ParaView's raw reader reads them
    # (vtkImageReader2 reads them top-down unless told otherwise: a mirrored volume).
    reader.SetFileLowerLeft(1)
    data = _run_reader(reader, path)
    image = vtkImageData()
    image.ShallowCopy(data)
    image.GetPointData().GetScalars().SetName("scalars")
    return image


def check_volume(image):
    """Raise HovrError unless the volume can be rendered; return a list of warnings."""
    if image is None or image.GetNumberOfPoints() == 0:
        raise HovrError("the volume is empty")
    scalars = image.GetPointData().GetScalars()
    if scalars is None:
        raise HovrError("the volume has no point scalars (cell data and unnamed field arrays "
                        "are not rendered)")
    if scalars.GetNumberOfComponents() != 1:
        raise HovrError("the volume's scalars have %d components; hovr renders one-component "
                        "scalars" % scalars.GetNumberOfComponents())
    if not scalars.IsNumeric():
        raise HovrError("the volume's scalars are not numeric")
    dims = image.GetDimensions()
    if min(dims) < 2:
        raise HovrError("the volume is %dx%dx%d: it needs at least 2 points along each axis"
                        % dims)
    warnings = []
    nan_count = count_nan(scalars)
    if nan_count == scalars.GetNumberOfTuples():
        raise HovrError("every value of the volume is NaN: there is nothing to render")
    if nan_count:
        warnings.append("the volume holds %d NaN values; they are rendered transparent"
                        % nan_count)
    # What every hovr renderer checks (tuple count, geometry, infinite values, range), here
    # for the stock methods too, which VTK's mappers would draw wrong without a word.
    from .hovrRenderingCore import vtkVolumeImageAlgorithm
    why = vtkVolumeImageAlgorithm.CheckVolume(image, scalars)
    if why:
        raise HovrError(why[0].lower() + why[1:].rstrip("."))
    return warnings


def count_nan(array):
    """Number of NaN values in a data array (0 for integer arrays)."""
    if array.GetDataType() not in (10, 11):  # VTK_FLOAT, VTK_DOUBLE
        return 0
    from vtkmodules.util.numpy_support import vtk_to_numpy
    import numpy
    return int(numpy.isnan(vtk_to_numpy(array)).sum())


def read_json(path, what):
    """The JSON document of a file, or a HovrError naming ``what`` the file should hold."""
    if not os.path.isfile(path):
        raise HovrError("%s file not found: %s" % (what, path))
    try:
        with open(path, "r", encoding="utf-8") as stream:
            return json.load(stream)
    except (OSError, ValueError) as error:
        raise HovrError("cannot read %s %s: %s" % (what, path, error)) from None


def read_transfer_function(path, need_opacity=True):
    """Read a ParaView transfer-function preset (an object or a list of them).

    Returns (vtkColorTransferFunction, vtkPiecewiseFunction, name) from the first preset that
    has both ``RGBPoints`` [x, r, g, b, ...] and ``Points`` [x, alpha, midpoint, sharpness,
    ...]. Colours are interpolated in the preset's ``ColorSpace`` (default RGB) as ParaView
    does; values outside the points take the end values. With ``need_opacity`` false, a
    colour-only preset (as ParaView's colour maps are) gives None for the opacity.
    """
    return transfer_function_from_preset(read_json(path, "transfer function"), path,
                                         need_opacity)


def transfer_function_from_preset(document, origin="preset", need_opacity=True):
    presets = document if isinstance(document, list) else [document]
    for preset in presets:
        if not isinstance(preset, dict):
            continue
        rgb, points = preset.get("RGBPoints"), preset.get("Points")
        if rgb is None and points is None:
            continue
        if rgb is None:
            raise HovrError("%s: the preset has no colour 'RGBPoints'" % origin)
        if points is None and need_opacity:
            raise HovrError("%s: the preset has no opacity 'Points' [x, alpha, midpoint, "
                            "sharpness, ...]; a colour map alone takes --opacity" % origin)
        color = vtkColorTransferFunction()
        set_color_space(color, preset.get("ColorSpace", "RGB"), origin)
        color.SetClamping(1)
        checked = ((rgb, 4, "RGBPoints"),) + (((points, 4, "Points"),) if points is not None
                                              else ())
        for values, stride, what in checked:
            if (not isinstance(values, list) or len(values) < stride or len(values) % stride
                    or not all(isinstance(v, (int, float)) and math.isfinite(v)
                               for v in values)):
                raise HovrError("%s: '%s' must be a list of finite numbers, %d per point"
                                % (origin, what, stride))
        for i in range(0, len(rgb), 4):
            color.AddRGBPoint(*rgb[i:i + 4])
        opacity = None
        if points is not None:
            opacity = vtkPiecewiseFunction()
            opacity.SetClamping(1)
            for i in range(0, len(points), 4):
                x, alpha, midpoint, sharpness = points[i:i + 4]
                if not 0.0 <= alpha <= 1.0:
                    raise HovrError("%s: opacity %g at %g is outside [0, 1]"
                                    % (origin, alpha, x))
                opacity.AddPoint(x, alpha, midpoint, sharpness)
        return color, opacity, preset.get("Name", os.path.basename(str(origin)))
    raise HovrError("%s holds no transfer function (objects with 'RGBPoints' and 'Points')"
                    % origin)


def make_volume_property(color, opacity, unit_distance=1.0):
    """A vtkVolumeProperty with linear interpolation and no shading."""
    if not (unit_distance > 0 and math.isfinite(unit_distance)):
        raise HovrError("the opacity unit distance must be positive, got %g" % unit_distance)
    prop = vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(unit_distance)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    return prop


CAMERA_KEYS = ("position", "focal_point", "view_up", "parallel_projection", "parallel_scale",
               "view_angle")


def camera_from_dict(values, origin="camera"):
    """A vtkCamera from {position, focal_point, view_up, parallel_projection, parallel_scale,
    view_angle} in VTK's meaning."""
    unknown = set(values) - set(CAMERA_KEYS)
    if unknown:
        raise HovrError("%s: unknown camera keys %s (known: %s)"
                        % (origin, sorted(unknown), ", ".join(CAMERA_KEYS)))
    camera = vtkCamera()
    for key, setter in (("position", camera.SetPosition), ("focal_point", camera.SetFocalPoint),
                        ("view_up", camera.SetViewUp)):
        if key in values:
            vector = values[key]
            if (not isinstance(vector, list) or len(vector) != 3
                    or not all(isinstance(v, (int, float)) and math.isfinite(v)
                               for v in vector)):
                raise HovrError("%s: '%s' must be three finite numbers" % (origin, key))
            setter(*vector)
    camera.SetParallelProjection(bool(values.get("parallel_projection", False)))
    if "parallel_scale" in values:
        if not values["parallel_scale"] > 0:
            raise HovrError("%s: 'parallel_scale' must be positive" % origin)
        camera.SetParallelScale(float(values["parallel_scale"]))
    if "view_angle" in values:
        if not 0 < values["view_angle"] < 180:
            raise HovrError("%s: 'view_angle' must lie in (0, 180) degrees" % origin)
        camera.SetViewAngle(float(values["view_angle"]))
    position, focal = camera.GetPosition(), camera.GetFocalPoint()
    if position == focal:
        raise HovrError("%s: the position equals the focal point" % origin)
    direction = [f - p for f, p in zip(focal, position)]
    up = camera.GetViewUp()
    cross = [direction[1] * up[2] - direction[2] * up[1],
             direction[2] * up[0] - direction[0] * up[2],
             direction[0] * up[1] - direction[1] * up[0]]
    if math.sqrt(sum(c * c for c in cross)) < 1e-12 * math.sqrt(sum(d * d for d in direction)):
        raise HovrError("%s: 'view_up' is parallel to the view direction" % origin)
    return camera


def read_camera(path):
    values = read_json(path, "camera")
    if not isinstance(values, dict):
        raise HovrError("%s: a camera is a JSON object" % path)
    return camera_from_dict(values, path)


def camera_to_dict(camera):
    return {"position": list(camera.GetPosition()), "focal_point": list(camera.GetFocalPoint()),
            "view_up": list(camera.GetViewUp()),
            "parallel_projection": bool(camera.GetParallelProjection()),
            "parallel_scale": camera.GetParallelScale(), "view_angle": camera.GetViewAngle()}


def default_camera(bounds, direction=(1.0, -1.6, 0.9), view_up=(0.0, 0.0, 1.0), angle=30.0,
                   parallel=False):
    """An oblique perspective camera that frames the bounding sphere of ``bounds``; with
    ``parallel``, the same view in parallel projection (scale: the sphere's radius)."""
    center = [(bounds[2 * a] + bounds[2 * a + 1]) / 2.0 for a in range(3)]
    radius = 0.5 * math.sqrt(sum((bounds[2 * a + 1] - bounds[2 * a]) ** 2 for a in range(3)))
    norm = math.sqrt(sum(d * d for d in direction))
    distance = radius / math.sin(math.radians(angle) / 2.0) * 1.02
    position = [c + distance * d / norm for c, d in zip(center, direction)]
    return camera_from_dict({"position": position, "focal_point": center,
                             "view_up": list(view_up), "view_angle": angle,
                             "parallel_projection": bool(parallel),
                             "parallel_scale": radius * 1.02})


def check_output_path(path):
    """Raise HovrError unless ``path`` can be written: its folder exists and is writable, and
    it is not a folder itself. Called before any work, so a bad path costs nothing."""
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise HovrError("cannot write %s: the folder %s does not exist" % (path, folder))
    if not os.access(folder, os.W_OK):
        raise HovrError("cannot write %s: the folder %s is not writable" % (path, folder))
    if os.path.isdir(path):
        raise HovrError("cannot write %s: it is a folder" % path)


def _run_writer(writer, path):
    catcher = _ErrorCatcher(writer)
    catcher_exec = _ErrorCatcher(writer.GetExecutive())
    try:
        with _VTKOutputCaptured():
            written = writer.Write()  # 1 or 0 from XML writers, None from image writers
    finally:
        catcher.detach()
        catcher_exec.detach()
    if written == 0 or writer.GetErrorCode() or catcher.messages or catcher_exec.messages:
        messages = catcher.messages + catcher_exec.messages
        reason = messages[0].splitlines()[-1] if messages else "write failed"
        raise HovrError("cannot write %s: %s" % (path, reason))


def write_vti(image, path):
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    _run_writer(writer, path)


def read_vti(path):
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader
    reader = vtkXMLImageDataReader()
    reader.SetFileName(path)
    return _run_reader(reader, path)


def rgba_to_png(image, path, array="RGBA", scale=1.0):
    """Write premultiplied float RGBA as an 8-bit RGB PNG composited over black; ``scale``
    brightens difference images."""
    import numpy
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGWriter
    values = vtk_to_numpy(image.GetPointData().GetArray(array))
    rgb = numpy.clip(numpy.nan_to_num(values[:, :3]) * scale, 0.0, 1.0)
    pixels = numpy.ascontiguousarray((rgb * 255.0 + 0.5).astype(numpy.uint8))
    out = vtkImageData()
    out.SetDimensions(image.GetDimensions())
    vtk_pixels = numpy_to_vtk(pixels, deep=True)
    vtk_pixels.SetName("RGB")
    out.GetPointData().SetScalars(vtk_pixels)
    writer = vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputData(out)
    _run_writer(writer, path)


def write_image(image, path):
    """Write an RGBA float image as .vti (exact) or .png (for looking)."""
    if path.lower().endswith(".png"):
        rgba_to_png(image, path)
    elif path.lower().endswith(".vti"):
        write_vti(image, path)
    else:
        raise HovrError("output must end in .vti or .png: %s" % path)
