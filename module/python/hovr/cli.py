"""The ``hovr`` command line: ``render``, ``bench`` and ``demo``.

Run through the ``./hovr`` script of the project (which builds, sets PYTHONPATH and provides
a display), or as ``python3 -m hovr.cli`` with the package importable.
"""

import argparse
import json
import math
import os
import sys
import time

from .io import HovrError


def _positive(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError("%r is not a number" % text) from None
    if not (value > 0 and math.isfinite(value)):
        raise argparse.ArgumentTypeError("must be a positive number, got %s" % text)
    return value


def _non_negative(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError("%r is not a number" % text) from None
    if not (value >= 0 and math.isfinite(value)):
        raise argparse.ArgumentTypeError("must be a non-negative number, got %s" % text)
    return value


def _size(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError("%r is not an integer" % text) from None
    if value < 1 or value > 16384:
        raise argparse.ArgumentTypeError("must lie in [1, 16384], got %s" % text)
    return value


def _ranged(low, high, what):
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError("%r is not an integer" % text) from None
        if value < low or value > high:
            raise argparse.ArgumentTypeError("%s must lie in [%d, %d], got %s" % (
                what, low, high, text))
        return value
    return parse


def _count(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError("%r is not an integer" % text) from None
    if value < 0:
        raise argparse.ArgumentTypeError("must not be negative, got %s" % text)
    return value


def build_parser():
    from .appearance import VIEWS
    from .io import RAW_TYPES
    from .methods import METHODS
    from .registry import CONES, INTERPOLATIONS, ORACLE_MODES, SPECULAR_MODELS
    parser = argparse.ArgumentParser(prog="hovr", description=(
        "Higher-order volume rendering for VTK: render with a method, measure its error "
        "against the reference integrator and its cost."))
    commands = parser.add_subparsers(dest="command", required=True)

    render = commands.add_parser("render", help="render one image", description=(
        "Render a volume with one method. Output: .vti (float RGBA, premultiplied, pixel (i, j) "
        "from left and bottom) or .png (composited over black, for looking). Raw input is read "
        "as numpy and ParaView read it: x fastest, rows in increasing y, slices in increasing "
        "z."))
    render.add_argument("--input", required=True, help=(
        "volume: .vti, .mhd, .nii, .nii.gz, .slc, legacy .vtk structured points, raw (with "
        "--dims and --type), marschner-lobb[:N], thin-features[:N] (sheets and tubes "
        "thinner than a voxel), curved-shells[:N] (thin curved shells, for shading) or "
        "blobs[:N] (a few Gaussian blobs in empty space, for adaptive sampling) for the "
        "generated test volumes"))
    render.add_argument("--dims", nargs=3, type=_size, metavar=("X", "Y", "Z"),
                        help="raw input: points along x, y, z (x fastest)")
    render.add_argument("--type", choices=sorted(RAW_TYPES), help="raw input: scalar type "
                        "(little-endian)")
    render.add_argument("--spacing", nargs=3, type=_positive, metavar=("X", "Y", "Z"),
                        help="raw input: voxel spacing (default 1 1 1)")
    render.add_argument("--header-bytes", type=_count, metavar="N", help="raw input: bytes "
                        "before the data (default 0: the file holds exactly the data)")
    render.add_argument("--tf", help="ParaView transfer-function preset JSON with RGBPoints "
                        "and Points in data units (default: --colormap and --opacity)")
    render.add_argument("--colormap", metavar="NAME|FILE", help="colours from a ParaView "
                        "colour preset, by name (e.g. 'Viridis (matplotlib)', 'Cool to Warm') "
                        "or JSON file, rescaled to the data range in its ColorSpace; replaces "
                        "the colours of --tf (default without --tf: black to white; white to black "
                        "for minip)")
    render.add_argument("--opacity", metavar="SPEC", help="opacity over the data range: ramp, "
                        "ramp-down, flat:A, F:A,F:A,... (F a fraction of the range) or a JSON "
                        "file with opacity Points (rescaled); replaces the opacity of --tf "
                        "(default without --tf: ramp-down for minip, ramp otherwise)")
    render.add_argument("--shade", action="store_true", help="light the volume with a "
                        "headlight (isosurfaces with the exact gradient; composite volumes "
                        "with the normalised gradient, preint1 pre-integrating the lighting)")
    render.add_argument("--gradient-interpolation", choices=sorted(INTERPOLATIONS),
                        default="nonlinear", help="--shade with preint1: how the normal is "
                        "interpolated between two samples: constant (their average), linear "
                        "(endpoint shading faded, Lum et al.) or nonlinear (along the arc, "
                        "Guetat et al.; default)")
    render.add_argument("--gooch", action="store_true", help="--shade: Gooch shading (cool "
                        "to warm tones) instead of Blinn-Phong (preint1 and the reference)")
    render.add_argument("--normals", metavar="ARRAY", help="--shade with preint1 and the "
                        "reference: the normals are this point array of 3-component vectors "
                        "(e.g. a .vti written by vtkGradientExaggeration) instead of the "
                        "gradient")
    render.add_argument("--exaggerate", type=_non_negative, metavar="EPS", help="--shade with "
                        "preint1 and the reference: exaggerate the normals first "
                        "(vtkGradientExaggeration, N + EPS (N - mean of the 5x5x5 box))")
    render.add_argument("--cone", choices=sorted(CONES), default="paper", help="--shade with "
                        "preint1 (and the reference with --specular cone): the cone that "
                        "stands for the specular lobe n: the paper's, of slope n (default), or "
                        "matched, of slope (n + 1) / 2, which gives the lobe's light")
    render.add_argument("--specular", choices=sorted(SPECULAR_MODELS), default="lobe",
                        help="--shade with the reference: VTK's specular lobe (default) or "
                        "the cone that shaded pre-integration uses")
    render.add_argument("--lmax", type=_ranged(0, 8, "--lmax"), default=3, metavar="L",
                        help="adaptive methods: the top level l_max; sampling distances reach "
                        "2^L base steps (default 3, the paper's)")
    render.add_argument("--oracle-epsilon", type=_non_negative, default=0.002, metavar="EPS",
                        help="adaptive methods: the change of opacity that makes a feature of "
                        "the oracle (default 0.002)")
    render.add_argument("--oracle-mode", choices=sorted(ORACLE_MODES), default="range",
                        help="adaptive methods: the oracle: range (opacity range over each "
                        "point's cells, sees transfer-function spikes between voxel values; "
                        "default), gradient (the paper's |grad opacity| > EPS), min (full "
                        "rate) or max (the largest distance everywhere)")
    render.add_argument("--opacity-unit-distance", type=_positive, default=1.0, metavar="U",
                        help="distance in world units over which the opacities hold "
                        "(default 1)")
    render.add_argument("--camera", help="camera JSON {position, focal_point, view_up, "
                        "parallel_projection, parallel_scale, view_angle}; default: --view")
    render.add_argument("--view", choices=sorted(VIEWS), default="iso", help="view direction "
                        "(+x looks along +x, as ParaView's buttons; write --view=-x for the minus "
                        "views), framing the whole volume (default iso: an oblique view)")
    render.add_argument("--zoom", type=_positive, default=1.0, help="closer by this factor "
                        "(default 1)")
    render.add_argument("--azimuth", type=float, default=0.0, metavar="DEG",
                        help="turn the view about the view-up axis through the centre")
    render.add_argument("--elevation", type=float, default=0.0, metavar="DEG",
                        help="turn the view up or down about the centre")
    render.add_argument("--parallel", action="store_true", help="parallel projection for "
                        "the view (always for the methods that draw only parallel ones)")
    render.add_argument("--size", nargs=2, type=_size, default=[512, 512], metavar=("W", "H"),
                        help="image size (default 512 512)")
    render.add_argument("--method", default="preint1", choices=sorted(METHODS),
                        help="rendering method (default preint1): " + "; ".join(
                            "%s = %s" % (m.name, m.description) for m in METHODS.values()))
    render.add_argument("--step", type=_positive, default=1.0, help="sampling step in units "
                        "of the smallest voxel spacing (default 1)")
    render.add_argument("--isovalue", type=float, action="append", metavar="V",
                        help="isosurface value in data units, repeatable (iso methods; the "
                        "nearest surface of any value is drawn)")
    render.add_argument("--blend", choices=["composite", "iso", "mip", "minip"],
                        help="blend mode of the reference method (other methods imply theirs)")
    render.add_argument("--output", help="output image, .vti or .png; iso methods add a "
                        "Depth array (world distance along the pixel ray, NaN on a miss), "
                        "projections MaxScalar or MinScalar (data units, NaN off the volume)")
    render.add_argument("--repeat", type=_count, default=0, metavar="N", help="after one "
                        "warm-up frame render N timed frames and print one JSON line")
    render.add_argument("--reference", metavar="REF.vti", help="also print the error "
                        "against this reference image")

    bench = commands.add_parser("bench", help="sweep datasets x methods x steps", description=(
        "Run a bench configuration (JSON): CSV, images, difference images and a plot of "
        "error against time per frame in the output folder."))
    bench.add_argument("config", help="bench configuration JSON (see presets/bench)")
    bench.add_argument("--output", default="bench-report", help="output folder "
                       "(default bench-report)")

    tables = commands.add_parser("tables", help="second-order table build times, CPU and GPU",
                                 description=(
        "Build the second-order pre-integration table of a transfer function on the CPU and "
        "on the GPU for several sizes and iteration counts; print the median build times and "
        "the largest difference between the two tables."))
    tables.add_argument("--tf", help="transfer function preset (default: neghip-spikes)")
    # The mapper's limits: 3D tables of 2 to 512 entries per axis, 1 to 4096 iterations.
    tables.add_argument("--sizes", nargs="+", type=_ranged(2, 512, "a table size"),
                        default=[64, 128, 192, 256])
    tables.add_argument("--iterations", nargs="+", type=_ranged(1, 4096, "iterations"),
                        default=[64])
    tables.add_argument("--repeat", type=_size, default=3)
    tables.add_argument("--no-gpu", action="store_true", help="CPU builds only")
    tables.add_argument("--csv", help="also write the results to this CSV file")

    demo = commands.add_parser("demo", help="run the default bench and print a summary")
    demo.add_argument("--output", default="report", help="output folder (default report)")
    demo.add_argument("--config", help="bench configuration (default presets/bench/demo.json)")
    return parser


def warn(message):
    print("hovr render: warning: " + message, file=sys.stderr)


def cmd_render(args):
    from . import bench as hb
    from . import io as hio
    from . import methods as hm
    if args.output:
        if not args.output.lower().endswith((".vti", ".png")):
            raise HovrError("--output must end in .vti or .png: %s" % args.output)
        hio.check_output_path(args.output)
    method = hm.get_method(args.method)
    if method.blend and args.blend and args.blend != method.blend:
        raise HovrError("--blend %s contradicts method %s, which renders %s" % (
            args.blend, method.name, method.blend))
    blend = method.blend or args.blend or "composite"
    if args.isovalue and blend != "iso":
        raise HovrError("--isovalue applies to isosurface rendering only; method %s renders "
                        "%s" % (method.name, blend))
    if blend == "iso" and not args.isovalue:
        raise HovrError("isosurface rendering needs at least one --isovalue")
    spec = {"input": args.input, "dims": args.dims, "type": args.type, "spacing": args.spacing,
            "header_bytes": args.header_bytes}
    image = hb.load_volume(spec)
    for warning in hio.check_volume(image):
        warn(warning)
    low, high = image.GetPointData().GetScalars().GetFiniteRange()
    prop = volume_property(args, blend, low, high)
    camera = render_camera(args, image, method)
    inside = 0
    for k, value in enumerate(args.isovalue or []):
        if not math.isfinite(value):
            raise HovrError("--isovalue must be finite, got %s" % value)
        if low <= value <= high:
            inside += 1
        else:
            warn("isovalue %g lies outside the data range [%g, %g]: it draws no surface"
                 % (value, low, high))
        prop.GetIsoSurfaceValues().SetValue(k, value)
    if args.isovalue and not inside:
        raise HovrError("no --isovalue lies inside the data range [%g, %g]: the image would "
                        "be empty" % (low, high))
    normals = args.normals
    if args.exaggerate is not None:
        if normals:
            raise HovrError("--exaggerate computes the normals: it does not combine with "
                            "--normals")
        image = hb.exaggerate_normals(image, args.exaggerate)
        normals = hb.EXAGGERATED_NORMALS
    scene = hm.Scene(image, prop, camera, args.size, blend)
    scene.shading = {"interpolation": args.gradient_interpolation, "gooch": args.gooch,
                     "specular": args.specular, "normals": normals, "cone": args.cone}
    scene.adaptive = {"lmax": args.lmax, "epsilon": args.oracle_epsilon,
                      "oracle": args.oracle_mode}
    if method.uses_step:
        scene.step_length(args.step)  # before any work: a step too small is an error
    renderer = hm.Renderer()
    start = time.perf_counter()
    try:
        result = renderer.render(args.method, scene, args.step, args.repeat)
    finally:
        renderer.close()
    seconds = time.perf_counter() - start
    if args.output:
        hio.write_image(result.image, args.output)
    print("hovr render: %s, %s, %dx%d, %.0f ms%s" % (
        args.output or "no --output, nothing written", args.method, args.size[0], args.size[1],
        1000.0 * seconds, " (%d frames)" % (args.repeat + 1) if args.repeat else ""),
        file=sys.stderr)
    line = result.summary(args.method, args.step) if args.repeat > 0 else None
    if args.reference:
        reference = hio.read_vti(args.reference)
        errors, _ = hm.compare(result.image, reference)
        line = line or {"method": args.method, "step": args.step}
        line.update(errors)
        if scene.blend != "composite":
            line.update(hm.compare_blend(result.image, reference, scene))
    if line is not None:
        print(json.dumps(line))
    return 0


def volume_property(args, blend, low, high):
    """The volume property of --tf, --colormap, --opacity, --opacity-unit-distance and
    --shade over the data range [low, high]."""
    from . import appearance as ha
    from . import io as hio
    color = opacity = None
    if args.tf:
        color, opacity, _ = hio.read_transfer_function(
            args.tf, need_opacity=args.opacity is None)
    if not high > low:
        high = low + max(1.0, abs(low) * 1e-6)  # flat data: any non-empty range
    if args.colormap:
        color = ha.colormap(args.colormap, low, high)
    elif color is None:
        color = ha.grey_ramp(low, high, inverted=blend == "minip")
    if args.opacity:
        opacity = ha.opacity(args.opacity, low, high)
    elif opacity is None:
        opacity = ha.opacity("ramp-down" if blend == "minip" else "ramp", low, high)
    prop = hio.make_volume_property(color, opacity, args.opacity_unit_distance)
    if args.shade:
        ha.shade(prop)
    return prop


def render_camera(args, image, method):
    """The camera of --camera, or of --view, --zoom, --azimuth, --elevation and --parallel;
    parallel-only methods get the view in parallel projection."""
    from . import appearance as ha
    from . import io as hio
    turned = args.view != "iso" or args.zoom != 1.0 or args.azimuth or args.elevation
    if args.camera:
        if turned or args.parallel:
            raise HovrError("--camera gives the whole view: it does not combine with --view, "
                            "--zoom, --azimuth, --elevation or --parallel")
        return hio.read_camera(args.camera)
    parallel = args.parallel or method.parallel_only
    if not turned:
        return hio.default_camera(image.GetBounds(), parallel=parallel)
    return ha.named_camera(image.GetBounds(), args.view, args.zoom, args.azimuth,
                           args.elevation, parallel=parallel)


def cmd_bench(args):
    from . import bench as hb
    rows, summary = hb.run(args.config, args.output,
                           log=lambda message: print(message, file=sys.stderr))
    sys.stdout.write(summary)
    return 0 if rows else 1


def cmd_demo(args):
    from . import bench as hb
    config = args.config or os.path.join(hb._project_root(), "presets", "bench", "demo.json")
    if not os.path.isfile(config):
        raise HovrError("demo configuration not found: %s" % config)
    rows, summary = hb.run(config, args.output,
                           log=lambda message: print(message, file=sys.stderr))
    sys.stdout.write(summary)
    print("\nhovr demo: %d runs; report in %s (results.csv, summary.txt, tradeoff.png, "
          "<dataset>_side_by_side.png, images/). At 1 voxel, against VTK:"
          % (len(rows), os.path.abspath(args.output)))
    sys.stdout.write(hb.format_headline(rows))
    return 0 if rows else 1


def cmd_tables(args):
    from . import bench as hb
    from . import tables as ht
    tf = args.tf or os.path.join(hb._project_root(), "presets", "transfer-functions",
                                 "neghip-spikes.json")
    rows = ht.measure(tf, args.sizes, args.iterations, args.repeat, gpu=not args.no_gpu)
    if args.csv:
        ht.write_csv(rows, args.csv)
    return 0


def main(argv=None):
    parser = build_parser()
    args = parser.parse_args(argv)
    handlers = {"render": cmd_render, "bench": cmd_bench, "demo": cmd_demo, "tables": cmd_tables}
    try:
        return handlers[args.command](args)
    except HovrError as error:
        print("hovr %s: error: %s" % (args.command, error), file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
