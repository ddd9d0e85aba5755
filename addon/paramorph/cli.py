"""Batch entry point: runs paramorph's operators on a file, the way an artist
would in the UI, and writes the result.

    blender -b --factory-startup --python <addons>/paramorph/cli.py -- COMMAND IN OUT [options]

    sphere  IN OUT [--weights conformal|barycentric] [--no-shape-key] [--no-repair]
    unwrap  IN OUT [--max-iterations N] [--margin M] [--pins place|exact]
    segment IN OUT [--mode extremities|features] [--threshold T] [--min-area A] [--no-repair]
                   [--normal-angle DEG] [--concavity-threshold C] [--spacing S]
    common: [--object NAME ...] [--backend auto|cpu|opencl]

    blender -b --factory-startup --python <addons>/paramorph/cli.py -- morph A B -o OUT.blend
                   [--frames N] [--start F] [--in-betweens K] [--straight] [--linear]
                   [--topology auto|keep|merged] [--no-repair]
                   [--pin A_VERTEX B_VERTEX ...] [--no-automatic]
                   [--source-object NAME] [--target-object NAME] [--backend ...]

    blender -b --factory-startup --python <addons>/paramorph/cli.py -- paste SOURCE TARGET OUT
                   (--select-ball X,Y,Z,R | --select-group NAME) --at X,Y,Z
                   [--source-object NAME] [--target-object NAME] [--rotation DEG] [--scale S]
                   [--blend-radius B] [--subdivision-level L] [--basis polyharmonic|wendland]
                   [--fit keep_form|follow_surface] [--resolution N] [--backend ...]

morph builds shape keys from A's shape to B's (K in-betweens, as rigid as
possible, or on straight lines with --straight): on A's own object when its
topology is kept (--topology keep, or auto when A has an armature, vertex
groups or UVs, as an OBJ with UVs does), else on the new object "<source> to
<target>" on the merged topology of both meshes; the keys are driven by that
object's "paramorph_morph" property, keyframed over N frames from frame F
(the scene's frame range is set to it), and the .blend is saved.
Each --pin takes vertex A_VERTEX of A exactly onto vertex B_VERTEX of B (Add
Pin); --no-automatic leaves the correspondence to the pins and the objects'
placement (Morph To's Automatic Matching off). It prints the candidate the
morph chose and its score, and what held exactly.

paste copies a feature from SOURCE's mesh (Copy Feature on the faces whose
centre lies in the ball X,Y,Z,R, or the faces of vertex group NAME; both in
the source object's coordinates) and pastes it onto TARGET's mesh at X,Y,Z
(the target object's coordinates, snapped to its surface) with Paste
Feature; OUT (.blend: both objects and the stored feature; .obj/.ply: the
target) gets the result.

IN is a .blend, .obj, .ply or .stl file; OUT a .blend, .obj or .ply file
(.obj and .ply keep the UVs; regions and shape keys only survive in .blend).
Every mesh object of IN is processed unless --object names some. An error
(bad mesh, missing or unreadable file, an operator's report, an OUT that
cannot be written) is printed to stderr in plain words, nothing is written
and the exit status is 1; usage errors exit 2. OUT is checked before any
work: an existing folder, or the same file as an input however spelled, is a
usage error (no input is ever overwritten); a folder that takes no new file is
an error. Missing folders above OUT are created when it is written. A .obj or
.ply is exported to a temporary file beside OUT and checked before it
replaces OUT (Blender's exporters may fail by only printing), so a failed
write leaves OUT as it was.

Run as a script, this file puts the folder holding the add-on on sys.path and
enables the add-on with addon_utils, as Blender does for a user; then it only
calls the add-on's operators (bpy.ops.paramorph.*), never the native module,
so a batch run does exactly what the same operators do in the UI."""
import argparse
import math
import os
import sys
import tempfile
import traceback

import bpy
import numpy as np

if __package__:
    PACKAGE = __package__
else:  # run as a script: make the add-on importable by its folder's name
    _HERE = os.path.dirname(os.path.abspath(__file__))
    PACKAGE = os.path.basename(_HERE)
    if os.path.dirname(_HERE) not in sys.path:
        sys.path.insert(0, os.path.dirname(_HERE))

PROG = "blender -b --factory-startup --python cli.py --"
INPUTS = (".blend", ".obj", ".ply", ".stl")
OUTPUTS = (".blend", ".obj", ".ply")
# Importers and exporters: Blender 4.x has C++ ones under wm.*; 3.4 has wm.obj_*
# and the Python add-ons import_mesh.* / export_mesh.* for PLY and STL.
IMPORTERS = {".obj": (("wm", "obj_import"), ("import_scene", "obj")),
             ".ply": (("wm", "ply_import"), ("import_mesh", "ply")),
             ".stl": (("wm", "stl_import"), ("import_mesh", "stl"))}
EXPORTERS = {".obj": (("wm", "obj_export"), ("export_scene", "obj")),
             ".ply": (("wm", "ply_export"), ("export_mesh", "ply"))}
REGION_ATTRIBUTE = "paramorph_region"


class CliError(Exception):
    """A problem to report in plain words (exit status 1)."""


def build_parser():
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("input", metavar="IN", help="input file: " + ", ".join(INPUTS))
    common.add_argument("output", metavar="OUT", help="output file: " + ", ".join(OUTPUTS))
    common.add_argument("--object", action="append", metavar="NAME", dest="objects",
                        help="mesh object to process (repeatable; default: every mesh object in IN)")
    common.add_argument("--backend", choices=("auto", "cpu", "opencl"),
                        help="compute backend (sets the add-on preference; default: auto)")

    parser = argparse.ArgumentParser(
        prog=PROG, description="Run paramorph's operators on a file in batch.")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    commands.required = True

    sphere = commands.add_parser("sphere", parents=[common],
                                 help="sphere map: UV layer and shape key 'Sphere'")
    sphere.add_argument("--weights", choices=("conformal", "barycentric"), default="conformal")
    sphere.add_argument("--no-shape-key", dest="shape_key", action="store_false",
                        help="write only the 'Sphere' UV layer")
    sphere.add_argument("--no-repair", dest="repair", action="store_false",
                        help="do not mend the mesh first (merge split seams, fill holes, turn it outward, "
                             "keep the largest part); fail on such a mesh instead")

    unwrap = commands.add_parser("unwrap", parents=[common],
                                 help="isometric unwrap of all faces into the active UV layer "
                                      "(pinned UVs stay where they are)")
    unwrap.add_argument("--max-iterations", type=int, metavar="N")
    unwrap.add_argument("--margin", type=float, metavar="M")
    unwrap.add_argument("--pins", choices=("place", "exact"), default="place",
                        help="pinned UVs place and turn their island, sized by the surface (default), "
                             "or stay exactly where they are")

    segment = commands.add_parser("segment", parents=[common],
                                  help="regions in face attribute 'paramorph_region'")
    segment.add_argument("--mode", choices=("extremities", "features"), default="extremities",
                         help="extremities: limbs by area stretch (closed genus-0 meshes); "
                              "features: creases and pockets")
    segment.add_argument("--no-repair", dest="repair", action="store_false",
                         help="extremities: do not mend the mesh first (see sphere --no-repair)")
    segment.add_argument("--threshold", type=float, help="extremities: log area stretch rise")
    segment.add_argument("--min-area", type=float,
                         help="smallest region, as a share of the surface")
    segment.add_argument("--normal-angle", type=float, metavar="DEG",
                         help="features: crease angle in degrees")
    segment.add_argument("--concavity-threshold", type=float,
                         help="features: pocket depth, share of the bounding-box diagonal")
    segment.add_argument("--spacing", type=float,
                         help="features: feature point spacing, share of the bounding-box diagonal")

    morph = commands.add_parser("morph", help="morph A's mesh into B's: a new object with shape keys, "
                                              "keyframed (writes a .blend)")
    morph.add_argument("source", metavar="A", help="source file: " + ", ".join(INPUTS))
    morph.add_argument("target", metavar="B", help="target file: " + ", ".join(INPUTS))
    morph.add_argument("-o", "--output", required=True, metavar="OUT", help="output .blend file")
    morph.add_argument("--frames", type=int, default=48, metavar="N", help="length of the morph (default 48)")
    morph.add_argument("--start", type=int, default=1, metavar="F", help="first frame (default 1)")
    morph.add_argument("--in-betweens", type=int, default=8, metavar="K",
                       help="shape keys between source and target (default 8)")
    morph.add_argument("--topology", choices=("auto", "keep", "merged"), default="auto",
                       help="keep A's own topology (shape keys on A's object), a merged one (a new object), or "
                            "auto: keep when A has an armature, vertex groups or UVs (default)")
    morph.add_argument("--straight", action="store_true",
                       help="in-betweens on straight lines (the thesis') instead of as rigid as possible")
    morph.add_argument("--linear", action="store_true", help="constant speed instead of eased")
    morph.add_argument("--no-repair", dest="repair", action="store_false",
                        help="do not mend the mesh first (merge split seams, fill holes, turn it outward, "
                             "keep the largest part); fail on such a mesh instead")
    morph.add_argument("--pin", nargs=2, type=int, action="append", dest="pins", default=[],
                       metavar=("A_VERTEX", "B_VERTEX"),
                       help="take vertex A_VERTEX of A exactly onto vertex B_VERTEX of B (repeatable; "
                            "0-based indices of the meshes as loaded)")
    morph.add_argument("--no-automatic", dest="automatic", action="store_false",
                       help="no automatic correspondence: only the pins and the objects' placement decide")
    morph.add_argument("--source-object", metavar="NAME", help="mesh object of A (when A has several)")
    morph.add_argument("--target-object", metavar="NAME", help="mesh object of B (when B has several)")
    morph.add_argument("--backend", choices=("auto", "cpu", "opencl"),
                       help="compute backend (sets the add-on preference; default: auto)")

    paste = commands.add_parser("paste", help="copy a feature from SOURCE and paste it onto TARGET")
    paste.add_argument("source", metavar="SOURCE", help="file with the feature: " + ", ".join(INPUTS))
    paste.add_argument("target", metavar="TARGET", help="file with the surface to paste on: " + ", ".join(INPUTS))
    paste.add_argument("output", metavar="OUT", help="output file: " + ", ".join(OUTPUTS))
    select = paste.add_mutually_exclusive_group(required=True)
    select.add_argument("--select-ball", type=_floats(4), metavar="X,Y,Z,R",
                        help="the feature: faces of SOURCE whose centre is within R of X,Y,Z (object space)")
    select.add_argument("--select-group", metavar="NAME",
                        help="the feature: faces of SOURCE whose vertices are all in vertex group NAME")
    paste.add_argument("--at", type=_floats(3), required=True, metavar="X,Y,Z",
                       help="where to paste, in TARGET's object coordinates (snapped to its surface)")
    paste.add_argument("--source-object", metavar="NAME", help="mesh object of SOURCE (when it has several)")
    paste.add_argument("--target-object", metavar="NAME", help="mesh object of TARGET (when it has several)")
    paste.add_argument("--rotation", type=float, metavar="DEG", help="turn about the surface normal (degrees)")
    paste.add_argument("--scale", type=float, metavar="S", help="size relative to the copied feature")
    paste.add_argument("--blend-radius", type=float, metavar="B", help="blend radius in feature radii (above 1.1)")
    paste.add_argument("--subdivision-level", type=int, metavar="L", help="-1 (auto) or 0..6")
    paste.add_argument("--basis", choices=("polyharmonic", "wendland"))
    paste.add_argument("--fit", choices=("keep_form", "follow_surface"))
    paste.add_argument("--resolution", type=int, metavar="N", help="displacement grid samples per side")
    paste.add_argument("--backend", choices=("auto", "cpu", "opencl"),
                       help="compute backend (sets the add-on preference; default: auto)")
    return parser, {"sphere": sphere, "unwrap": unwrap, "segment": segment, "morph": morph, "paste": paste}


def _floats(count):
    """argparse type: `count` comma-separated numbers."""
    def parse(text):
        try:
            values = tuple(float(x) for x in text.split(","))
        except ValueError:
            values = ()
        if len(values) != count or not all(math.isfinite(v) for v in values):
            raise argparse.ArgumentTypeError(f"expected {count} comma-separated numbers, not {text!r}")
        return values
    parse.__name__ = f"{count} numbers"
    return parse


VECTOR_FLAGS = ("--select-ball", "--at")


def _join_vectors(argv):
    """`--at -1,0,2` as `--at=-1,0,2`: argparse takes a value starting with '-'
    (a negative first coordinate) for an option otherwise."""
    out = []
    for arg in argv:
        if out and out[-1] in VECTOR_FLAGS and arg.startswith("-") and "," in arg:
            out[-1] = f"{out[-1]}={arg}"
        else:
            out.append(arg)
    return out


def parse_args(argv):
    parser, subparsers = build_parser()
    args = parser.parse_args(_join_vectors(list(argv)))
    parser = subparsers[args.command]  # later errors show the command's usage
    if args.command == "morph":
        files = (("A", args.source, INPUTS), ("B", args.target, INPUTS), ("OUT", args.output, (".blend",)))
    elif args.command == "paste":
        files = (("SOURCE", args.source, INPUTS), ("TARGET", args.target, INPUTS), ("OUT", args.output, OUTPUTS))
    else:
        files = (("IN", args.input, INPUTS), ("OUT", args.output, OUTPUTS))
    for label, path, allowed in files:
        if os.path.splitext(path)[1].lower() not in allowed:
            parser.error(f"{label} must end in {', '.join(allowed)}, not {path!r}")
    check_output_name(parser, files)
    if args.command == "segment":
        only = {"extremities": ("threshold",),
                "features": ("normal_angle", "concavity_threshold", "spacing")}
        for mode, names in only.items():
            for name in names:
                if args.mode != mode and getattr(args, name) is not None:
                    parser.error(f"--{name.replace('_', '-')} applies to --mode {mode}")
    if args.command == "morph" and (args.frames < 2 or args.in_betweens < 0):
        parser.error("--frames must be at least 2 and --in-betweens at least 0")
    if args.command == "morph":
        check_pins(parser, args.pins)
    if args.command == "paste" and args.select_ball is not None and args.select_ball[3] <= 0:
        parser.error("--select-ball needs a radius above 0")
    args.parser = parser
    return args


def same_file(a, b):
    """Whether paths `a` and `b` name one file (however spelled: relative,
    through a symbolic link, or a hard link to it)."""
    if os.path.realpath(a) == os.path.realpath(b):
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist
        return False


def check_output_name(parser, files):
    """Usage errors before any work: OUT (the last of `files`) is an existing
    folder or other non-file, or is one of the input files (which the command
    would overwrite)."""
    label, out, _ = files[-1]
    if os.path.exists(out) and not os.path.isfile(out):
        kind = "a folder" if os.path.isdir(out) else "not a regular file"
        parser.error(f"{label} {out!r} is {kind}: name the file to write")
    for name, path, _ in files[:-1]:
        if same_file(path, out):
            parser.error(f"{label} {out!r} is the same file as {name}: write the result to another "
                         f"file ({name} is never overwritten)")


def check_pins(parser, pins):
    """--pin indices are not negative and no vertex is pinned twice (Add Pin
    would let the later pin replace the earlier one silently)."""
    seen = ({}, {})
    for i, pin in enumerate(pins):
        for side, (vertex, label) in enumerate(zip(pin, "AB")):
            if vertex < 0:
                parser.error(f"--pin {pin[0]} {pin[1]}: vertex indices start at 0")
            if vertex in seen[side]:
                first = pins[seen[side][vertex]]
                parser.error(f"--pin {first[0]} {first[1]} and --pin {pin[0]} {pin[1]} both pin vertex "
                             f"{vertex} of {label}")
            seen[side][vertex] = i


# --- Blender side -------------------------------------------------------------

def find_operator(module, name):
    """bpy.ops.<module>.<name>, or None when it is not registered (hasattr on
    bpy.ops is always true, dir() lists what exists)."""
    namespace = getattr(bpy.ops, module)
    return getattr(namespace, name) if name in dir(namespace) else None


def operator_options(op, **options):
    """Only the options this Blender's version of `op` has."""
    names = {p.identifier for p in op.get_rna_type().properties}
    return {k: v for k, v in options.items() if k in names}


def call_operator(op, **options):
    """Runs an operator; its ERROR report (or a poll failure) becomes a CliError."""
    try:
        status = op(**options)
    except RuntimeError as error:
        lines = [line.strip() for line in str(error).strip().splitlines() if line.strip()]
        lines = [line[len("Error: "):] if line.startswith("Error: ") else line for line in lines]
        if lines and lines[0].startswith("Python: Traceback"):  # a Python operator's exception:
            lines = [line for line in lines if not line.startswith("Location:")][-1:]  # its last line
        raise CliError("; ".join(lines) or f"{op.idname_py()} failed") from None
    if "FINISHED" not in status:
        raise CliError(f"{op.idname_py()} did not finish ({', '.join(sorted(status))})")
    return status


def load(path):
    ext = os.path.splitext(path)[1].lower()
    if ext == ".blend":
        call_operator(bpy.ops.wm.open_mainfile, filepath=path, load_ui=False)
        return
    bpy.ops.wm.read_factory_settings(use_empty=True)
    for module, name in IMPORTERS[ext]:
        op = find_operator(module, name)
        if op is not None:
            call_operator(op, filepath=path)
            return
    raise CliError(f"this Blender has no {ext} importer")


def enable_addon(backend):
    """Enables the add-on as a user does (unless it is already on, e.g. as the
    extension bl_ext.<repo>.paramorph) and sets the backend preference."""
    import addon_utils

    enabled = [a.module for a in bpy.context.preferences.addons
               if a.module == PACKAGE or a.module.endswith("." + PACKAGE)]
    package = enabled[0] if enabled else PACKAGE
    if not enabled and addon_utils.enable(package, default_set=True) is None:
        raise CliError(f"the {package} add-on could not be enabled (see the messages above)")
    native = sys.modules[f"{package}.native"]
    if native.native is None:
        raise CliError(native.load_error)
    if backend is not None:
        bpy.context.preferences.addons[package].preferences.backend = backend
    return package


def check_ranges(parser, op, options, flags):
    """Values outside an operator property's range are usage errors, not
    silently clamped as bpy.ops would."""
    properties = op.get_rna_type().properties
    for name, value in options.items():
        prop = properties[name]
        if prop.type not in ("INT", "FLOAT") or prop.hard_min <= value <= prop.hard_max:
            continue
        shown = [math.degrees(x) if prop.subtype == "ANGLE" else x
                 for x in (value, prop.hard_min, prop.hard_max)]
        flag = flags.get(name, name)
        if prop.hard_max >= 1e30:
            parser.error(f"{flag} {shown[0]:g} is below its minimum {shown[1]:g}")
        parser.error(f"{flag} {shown[0]:g} is outside [{shown[1]:g}, {shown[2]:g}]")


def mesh_objects(names):
    scene_objects = bpy.context.view_layer.objects
    if names:
        missing = [n for n in names if n not in scene_objects]
        not_mesh = [n for n in names if n in scene_objects and scene_objects[n].type != "MESH"]
        if missing or not_mesh:
            meshes = sorted(o.name for o in scene_objects if o.type == "MESH")
            problem = (f"no object named {', '.join(map(repr, missing))}" if missing
                       else f"{', '.join(map(repr, not_mesh))} is not a mesh")
            raise CliError(f"{problem} (mesh objects: {', '.join(meshes) or 'none'})")
        return [scene_objects[n] for n in names]
    objects = sorted((o for o in scene_objects if o.type == "MESH"), key=lambda o: o.name)
    if not objects:
        raise CliError("no mesh object in the input")
    return objects


def object_mode():
    obj = bpy.context.view_layer.objects.active
    if obj is not None and obj.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")


def activate(obj, objects=None):
    """`obj` active, it (or `objects`) the only selection, Object Mode."""
    object_mode()
    view_layer = bpy.context.view_layer
    chosen = set(o.name for o in (objects or [obj]))
    for other in view_layer.objects:  # objects, not mesh elements
        other.select_set(other.name in chosen)
    view_layer.objects.active = obj


def sphere(args, obj):
    op = bpy.ops.paramorph.sphere_map
    call_operator(op, weights=args.weights, shape_key=args.shape_key, repair=args.repair)
    mesh = obj.data
    written = "UV layer 'Sphere'" + (" and shape key 'Sphere'" if args.shape_key else "")
    return f"{written} ({len(mesh.vertices)} vertices, {len(mesh.polygons)} faces)"


def unwrap_options(args):
    options = {"pin_mode": args.pins.upper()}
    if args.max_iterations is not None:
        options["max_iterations"] = args.max_iterations
    if args.margin is not None:
        options["margin"] = args.margin
    return options


def unwrap(args, obj):
    op = bpy.ops.paramorph.isometric_unwrap
    call_operator(bpy.ops.object.mode_set, mode="EDIT")
    try:
        call_operator(bpy.ops.mesh.select_all, action="SELECT")
        call_operator(op, **unwrap_options(args))
    finally:
        bpy.ops.object.mode_set(mode="OBJECT")
    mesh = obj.data
    layer = mesh.uv_layers.active
    return f"UV layer '{layer.name if layer else '?'}' ({len(mesh.polygons)} faces)"


def segment_call(args):
    if args.mode == "extremities":
        options = {"threshold": args.threshold, "min_area": args.min_area, "repair": args.repair}
        return bpy.ops.paramorph.segment_extremities, options
    options = {"normal_angle": None if args.normal_angle is None else math.radians(args.normal_angle),
               "concavity_threshold": args.concavity_threshold,
               "min_area": args.min_area, "spacing": args.spacing}
    return bpy.ops.paramorph.detect_feature_regions, options


def segment(args, obj):
    op, options = segment_call(args)
    call_operator(op, **{k: v for k, v in options.items() if v is not None})
    regions = obj.paramorph_regions
    return f"{regions} region{'' if regions == 1 else 's'} in face attribute '{REGION_ATTRIBUTE}'"


COMMANDS = {"sphere": sphere, "unwrap": unwrap, "segment": segment}
FLAGS = {"threshold": "--threshold", "min_area": "--min-area", "normal_angle": "--normal-angle",
         "concavity_threshold": "--concavity-threshold", "spacing": "--spacing",
         "max_iterations": "--max-iterations", "margin": "--margin"}


def check_options(args):
    """Operator-level checks before any work: every value is in its property's range."""
    if args.command == "unwrap":
        op, options = bpy.ops.paramorph.isometric_unwrap, unwrap_options(args)
    elif args.command == "segment":
        op, options = segment_call(args)
        options = {k: v for k, v in options.items() if v is not None}
    else:
        return
    check_ranges(args.parser, op, options, FLAGS)


def check_writable(path):
    """Before any work: OUT's folder, or the nearest existing folder above it
    (save creates the missing ones), takes a new file; CliError otherwise. The
    probe is an unnamed temporary file: nothing is left behind."""
    existing = os.path.dirname(os.path.abspath(path))
    while not os.path.exists(existing):
        existing = os.path.dirname(existing)
    if not os.path.isdir(existing):
        raise CliError(f"cannot write {path}: {existing} is a file, not a folder")
    try:
        with tempfile.TemporaryFile(dir=existing):
            pass
    except OSError as error:
        raise CliError(f"cannot write {path}: the folder {existing} takes no new file "
                       f"({error.strerror or error})") from None


def check_written(written, path):
    """`written` is a file and not empty (Blender's exporters may fail by
    only printing a message); CliError naming OUT (`path`) otherwise."""
    size = os.path.getsize(written) if os.path.isfile(written) else None
    if not size:
        what = "nothing" if size is None else "an empty file"
        raise CliError(f"cannot write {path}: Blender wrote {what} (see its messages above)")


def save(path, objects, command):
    """Writes OUT; CliError (and OUT as it was) when that fails. .obj and .ply
    are exported to a temporary file beside OUT, checked, then renamed to it."""
    ext = os.path.splitext(path)[1].lower()
    folder = os.path.dirname(path)
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as error:
        raise CliError(f"cannot write {path}: cannot create the folder {folder}: "
                       f"{error.strerror or error}") from None
    if ext == ".blend":
        call_operator(bpy.ops.wm.save_as_mainfile, filepath=path, check_existing=False)
        check_written(path, path)
        return
    activate(objects[0], objects)
    if command == "sphere":  # the exporters write the active UV layer
        for obj in objects:
            obj.data.uv_layers.active = obj.data.uv_layers["Sphere"]
    for module, name in EXPORTERS[ext]:
        op = find_operator(module, name)
        if op is not None:
            break
    else:
        raise CliError(f"this Blender has no {ext} exporter")
    stem = os.path.splitext(os.path.basename(path))[0]
    partial = os.path.join(folder, f".{stem}.paramorph-{os.getpid()}{ext}")  # hidden, this run's own
    try:
        call_operator(op, **operator_options(
            op, filepath=partial, check_existing=False,
            export_selected_objects=True, use_selection=True,   # 4.x / 3.4 names
            export_uv=True, use_uv_coords=True,
            export_colors="SRGB" if name == "ply_export" else True, use_colors=True,
            export_materials=False))
        check_written(partial, path)
        os.replace(partial, path)
    except OSError as error:
        raise CliError(f"cannot write {path}: {error.strerror or error}") from None
    finally:
        if os.path.lexists(partial):
            os.remove(partial)


def unreadable_blend(label, path, error):
    """The message for a .blend that Blender cannot open (`error` its OSError)."""
    detail = " ".join(str(error).split())
    detail = detail[len("Error: "):] if detail.startswith("Error: ") else detail
    if not detail or "failed to open blend file" in detail:  # all 'load:' says: not a .blend at all
        return f"{label}: {path} is not a .blend file"
    return f"{label}: {path} cannot be read: {detail}"


def check_input(label, path):
    """An input file exists (CliError naming it, after `label` when given, otherwise)."""
    named = f"{label}: {path}" if label else path
    if os.path.isdir(path):
        raise CliError(f"{named} is a folder, not a file")
    if not os.path.isfile(path):
        raise CliError(f"{named}: no such file")


def _added_mesh_object(path, wanted, label):
    """Adds the mesh objects of a .blend (appended; only `wanted` when given) or of
    a mesh file (imported) to the scene; returns the one (or the one named `wanted`)."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".blend":
        try:
            with bpy.data.libraries.load(path, link=False) as (data_from, data_to):
                names = list(data_from.objects)
                data_to.objects = [wanted] if wanted in names else ([] if wanted else names)
        except OSError as error:  # not a .blend, or a damaged one
            raise CliError(unreadable_blend(label, path, error)) from None
        added = [o for o in data_to.objects if o is not None]
        for obj in added:
            bpy.context.scene.collection.objects.link(obj)
    else:
        before = set(bpy.context.scene.objects)
        for module, name in IMPORTERS[ext]:
            op = find_operator(module, name)
            if op is not None:
                call_operator(op, filepath=path)
                break
        else:
            raise CliError(f"this Blender has no {ext} importer")
        added = [o for o in bpy.context.scene.objects if o not in before]
    meshes = sorted((o for o in added if o.type == "MESH"), key=lambda o: o.name)
    if wanted is not None:
        # An object renamed on arrival ("Name.001": the scene had one) still counts.
        chosen = [o for o in meshes if o.name == wanted or o.name.rsplit(".", 1)[0] == wanted]
        if not chosen:
            raise CliError(f"{label} has no mesh object named {wanted!r}")
        return chosen[0]
    if len(meshes) != 1:
        flag = "--source-object" if label in ("A", "SOURCE") else "--target-object"
        raise CliError(f"{label} has {len(meshes)} mesh objects ({', '.join(o.name for o in meshes) or 'none'}): "
                       f"name one with {flag}")
    return meshes[0]


def start_two_file_command(args, source_label, target_label):
    """For morph and paste: both input files exist (else CliError naming the
    missing one) and OUT can be written, then an empty scene with the add-on enabled."""
    for label, path in ((source_label, args.source), (target_label, args.target)):
        check_input(label, path)
    check_writable(args.output)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return enable_addon(args.backend)


def morph_main(args):
    name = "paramorph morph"
    try:
        package = start_two_file_command(args, "A", "B")
        source, target = (_added_mesh_object(os.path.abspath(path), wanted, label)
                          for label, path, wanted in (("A", args.source, args.source_object),
                                                      ("B", args.target, args.target_object)))
        activate(target, [source, target])
        for a, b in args.pins:
            call_operator(bpy.ops.paramorph.add_pin, vertex_a=a, vertex_b=b)
        scene = bpy.context.scene
        scene.frame_start, scene.frame_end = args.start, args.start + args.frames - 1
        call_operator(bpy.ops.paramorph.morph_to, frame_start=scene.frame_start, frame_end=scene.frame_end,
                      in_betweens=args.in_betweens, easing="LINEAR" if args.linear else "EASE",
                      interpolation="LINEAR" if args.straight else "ARAP", topology=args.topology.upper(),
                      automatic=args.automatic, use_preview=False, repair=args.repair)
        summary = sys.modules[f"{package}.morph.operators"].last_morph
        result = bpy.data.objects[summary["object"]]  # the new object, or A's own when its topology is kept
        keys = len(result.data.shape_keys.key_blocks) - 1
        print(f"{name}: {result.name}: {len(result.data.vertices)} vertices, {len(result.data.polygons)} faces, "
              f"{keys} shape key{'' if keys == 1 else 's'}, frames {scene.frame_start}-{scene.frame_end}",
              flush=True)
        print(f"{name}: {summary['chosen']}; {summary['held']}", flush=True)
        if "hausdorff" in summary:
            print(f"{name}: kept {result.name}'s topology; Hausdorff distance to the target "
                  f"{100 * summary['hausdorff']:.2g} % of its diagonal", flush=True)
        for note in summary["notes"]:
            print(f"{name}: {note}", flush=True)
        out = os.path.abspath(args.output)
        save(out, None, "morph")
    except CliError as error:
        print(f"{name}: error: {error}", file=sys.stderr, flush=True)
        return 1
    print(f"{name}: wrote {out}", flush=True)
    return 0


PASTE_FLAGS = {"rotation": "--rotation", "scale": "--scale", "blend_radius": "--blend-radius",
               "subdivision_level": "--subdivision-level", "resolution": "--resolution"}


def paste_options(args):
    """Paste Feature's options given on the command line (the operator's defaults otherwise)."""
    options = {"scale": args.scale, "blend_radius": args.blend_radius,
               "subdivision_level": args.subdivision_level, "basis": args.basis, "fit": args.fit,
               "rotation": None if args.rotation is None else math.radians(args.rotation)}
    return {k: v for k, v in options.items() if v is not None}


def select_feature_faces(args, source):
    """Selects the feature's faces of `source` (Edit Mode, face select) by ball or vertex group."""
    activate(source)
    mesh = source.data
    if args.select_group is not None:
        if args.select_group not in source.vertex_groups:
            groups = ", ".join(g.name for g in source.vertex_groups) or "none"
            raise CliError(f"{source.name} has no vertex group {args.select_group!r} (groups: {groups})")
        call_operator(bpy.ops.object.mode_set, mode="EDIT")
        call_operator(bpy.ops.mesh.select_mode, type="VERT")
        call_operator(bpy.ops.mesh.select_all, action="DESELECT")
        source.vertex_groups.active = source.vertex_groups[args.select_group]
        call_operator(bpy.ops.object.vertex_group_select)
        call_operator(bpy.ops.mesh.select_mode, type="FACE")  # faces whose vertices are all in it
        bpy.ops.object.mode_set(mode="OBJECT")
        selected = np.empty(len(mesh.polygons), dtype=bool)
        mesh.polygons.foreach_get("select", selected)
    else:
        x, y, z, r = args.select_ball
        centres = np.empty(3 * len(mesh.polygons), dtype=np.float32)
        mesh.polygons.foreach_get("center", centres)
        selected = np.linalg.norm(centres.reshape(-1, 3) - (x, y, z), axis=1) <= r
        vertices = np.zeros(len(mesh.vertices), dtype=bool)
        loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
        mesh.loops.foreach_get("vertex_index", loop_vertex)
        loop_total = np.empty(len(mesh.polygons), dtype=np.int32)
        mesh.polygons.foreach_get("loop_total", loop_total)
        vertices[loop_vertex[np.repeat(selected, loop_total)]] = True
        mesh.vertices.foreach_set("select", vertices)
        mesh.edges.foreach_set("select", np.zeros(len(mesh.edges), dtype=bool))
        mesh.polygons.foreach_set("select", selected)
        mesh.update()
    call_operator(bpy.ops.object.mode_set, mode="EDIT")
    bpy.context.tool_settings.mesh_select_mode = (False, False, True)
    return int(selected.sum())


def paste_main(args):
    name = "paramorph paste"
    try:
        start_two_file_command(args, "SOURCE", "TARGET")
        options = paste_options(args)
        check_ranges(args.parser, bpy.ops.paramorph.paste_feature, options, PASTE_FLAGS)
        copy_options = {} if args.resolution is None else {"resolution": args.resolution}
        check_ranges(args.parser, bpy.ops.paramorph.copy_feature, copy_options, PASTE_FLAGS)
        source = _added_mesh_object(os.path.abspath(args.source), args.source_object, "SOURCE")
        target = _added_mesh_object(os.path.abspath(args.target), args.target_object, "TARGET")
        if source == target:
            raise CliError("SOURCE and TARGET name the same object")
        selected = select_feature_faces(args, source)
        try:
            call_operator(bpy.ops.paramorph.copy_feature, **copy_options)
        except CliError as error:
            raise CliError(f"{source.name}: {error}") from None
        finally:
            object_mode()
        print(f"{name}: {source.name}: copied the feature of {selected} faces", flush=True)
        activate(target)
        before = len(target.data.polygons)
        try:
            call_operator(bpy.ops.paramorph.paste_feature, location=args.at, **options)
        except CliError as error:
            raise CliError(f"{target.name}: {error}") from None
        print(f"{name}: {target.name}: {before} -> {len(target.data.polygons)} faces, "
              f"{len(target.data.vertices)} vertices", flush=True)
        out = os.path.abspath(args.output)
        save(out, [target], "paste")
    except CliError as error:
        print(f"{name}: error: {error}", file=sys.stderr, flush=True)
        return 1
    print(f"{name}: wrote {out}", flush=True)
    return 0


def main(argv):
    """Runs one command; returns the exit status (usage errors exit 2 through argparse)."""
    args = parse_args(argv)
    if args.command == "morph":
        return morph_main(args)
    if args.command == "paste":
        return paste_main(args)
    name = f"paramorph {args.command}"
    try:
        check_input(None, args.input)
        check_writable(args.output)
        load(os.path.abspath(args.input))
        enable_addon(args.backend)
        check_options(args)
        objects = mesh_objects(args.objects)
        for obj in objects:
            activate(obj)
            try:
                summary = COMMANDS[args.command](args, obj)
            except CliError as error:
                raise CliError(f"{obj.name}: {error}") from None
            print(f"{name}: {obj.name}: {summary}", flush=True)
        object_mode()
        out = os.path.abspath(args.output)
        save(out, objects, args.command)
    except CliError as error:
        print(f"{name}: error: {error}", file=sys.stderr, flush=True)
        return 1
    if args.command == "segment" and not out.endswith(".blend"):
        print(f"{name}: note: {os.path.splitext(out)[1]} keeps no '{REGION_ATTRIBUTE}' "
              "attribute; write a .blend to keep the regions", file=sys.stderr)
    print(f"{name}: wrote {out}", flush=True)
    return 0


def script_argv():
    """The arguments after `--` (Blender's own come before it)."""
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def run_as_script():
    try:
        code = main(script_argv())
    except SystemExit:
        raise
    except Exception:  # a bug: show it, and fail even without --python-exit-code
        traceback.print_exc()
        code = 1
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
    if code:
        sys.exit(code)


if __name__ == "__main__":
    run_as_script()
