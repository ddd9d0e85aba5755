"""Native errors in plain words for Blender reports: what is wrong with the
mesh and the Blender tool that fixes it, instead of a traceback."""
import numpy as np

from . import blender_numbers
from .native import native


def _count(n, word):
    return f"{n} {word}{'' if n == 1 else 's'}"


def describe(error, V=None, F=None, repair=None, numbering=None, constraints=None):
    """A one-line message for `error`; V, F (the arrays sent to the native
    call) let it count holes and components. repair: None when the operator
    has no Repair option, else whether it was on (the advice differs).
    numbering: a blender_numbers.MeshNumbering of the mesh V, F came from,
    to name its elements as Blender numbers them. constraints: what a
    ConstraintError is about: "uv" (pinned UVs, Isometric Unwrap), "pins"
    (the morph's pins and pairs, which the native text names), or None (the
    native text says what cannot be met)."""
    text = _describe(error, V, F, repair, numbering, constraints)
    if repair is False and native is not None and isinstance(
            error, (native.NotClosedError, native.DisconnectedError, native.NonManifoldError,
                    native.DegenerateFaceError)):
        text += ", or turn on Repair (in the operator's options)"
    return text


def _coincident_vertices(V, F):
    """How many vertices the faces use that lie exactly on another one
    (seams split on export): what makes a welded-looking mesh open or in parts."""
    if V is None or F is None or len(F) == 0:
        return 0
    used = np.unique(np.asarray(F).ravel())
    points = np.ascontiguousarray(np.asarray(V)[used])
    return len(points) - len(np.unique(points, axis=0))


def _describe(error, V, F, repair, numbering, constraints):
    pm = native
    if pm is None:
        return str(error)
    if isinstance(error, pm.Cancelled):  # before validating: nothing to count
        return "cancelled: the mesh was left as it was"
    report = None
    if V is not None and F is not None:
        try:
            report = pm.validate(V, F)
        except Exception:  # the arrays themselves are bad: fall back to the error text
            report = None
    selection = _selection_message(pm, error)
    if selection is not None:
        return selection
    if isinstance(error, (pm.NotClosedError, pm.DisconnectedError)):
        coincident = _coincident_vertices(V, F)
        if coincident:
            vertices = "1 vertex" if coincident == 1 else f"{coincident} vertices"
            return (f"mesh has {vertices} lying on other vertices (seams split on export), "
                    "so it looks open or in parts: Mesh > Clean Up > Merge by Distance")
    if isinstance(error, pm.NotClosedError):
        holes = report.boundary_loops if report is not None else None
        head = f"mesh has {_count(holes, 'hole')}" if holes else "mesh is not closed"
        return f"{head}: close them (Fill Holes) first"
    if isinstance(error, pm.NotOpenError):
        return "the selected faces form a closed surface: mark a seam to cut it open first"
    if isinstance(error, pm.NotGenusZeroError):
        genus = report.genus if report is not None and report.genus > 0 else None
        head = f"mesh has {_count(genus, 'handle')} (genus {genus})" if genus else "mesh has handles"
        if repair:
            return (f"{head}: Repair mends seams and fills holes but cannot remove handles; it must be a "
                    "sphere-like surface (cut or fill the handles first)")
        return f"{head}: it must be a sphere-like surface (cut or fill the handles first)"
    if isinstance(error, pm.DisconnectedError):
        parts = report.components if report is not None and report.components > 1 else None
        head = f"mesh has {_count(parts, 'separate part')}" if parts else "mesh has separate parts"
        return f"{head}: separate them (Separate > By Loose Parts) or delete loose geometry first"
    if numbering is not None and report is not None and isinstance(error, (pm.NonManifoldError,
                                                                           pm.DegenerateFaceError)):
        text = blender_numbers.describe_problem(str(error), report, numbering)
        if text is not None:
            return text
    # The native messages already say what is wrong and how to select it: wrapped
    # again they said "not manifold" twice.
    if isinstance(error, pm.NonManifoldError):
        text = str(error)
        return text if text.startswith("mesh ") else (
            f"mesh is not manifold ({text}): Select > All by Trait > Non Manifold shows where")
    if isinstance(error, pm.DegenerateFaceError):
        text = str(error)
        return text if text.startswith("mesh ") else (
            f"mesh has zero-area faces ({text}): Mesh > Clean Up > Degenerate Dissolve fixes them")
    if isinstance(error, pm.ConstraintError):
        return _constraint_message(error, constraints)
    if isinstance(error, pm.InvalidInputError):
        return f"invalid input: {error}"
    device_error = getattr(pm, "DeviceError", None)  # older builds lack it
    if device_error is not None and isinstance(error, device_error):
        return (f"the OpenCL device failed ({error}): choose the CPU backend in the add-on "
                "preferences (--backend cpu on the command line)")
    if isinstance(error, pm.ComputeError):
        return _compute_message(error, repair)
    return f"{type(error).__name__}: {error}"


def _constraint_message(error, constraints):
    """Constraints that cannot all be met, in the words of the caller's constraints."""
    if constraints == "uv":
        return f"the pinned UVs cannot all be met without folds ({error}): unpin or move some"
    if constraints == "pins":  # the native text names the pins or pairs and what they do
        return f"{error}: move or remove the pins or pairs it names"
    return str(error)


def _compute_message(error, repair):
    """A computation that could not finish (no fold-free map, a solver that did
    not converge): what failed, and what to change on the mesh. Not the device's
    fault: the CPU backend fails the same way."""
    mend = "turn on Repair (in the operator's options), " if repair is False else ""
    return (f"the computation could not finish ({error}): {mend}try Mesh > Clean Up, a Remesh or "
            "Decimate of very thin parts, or report the mesh")


def _selection_message(pm, error):
    """Cut-and-paste errors (classes looked up by name: older builds lack some)."""
    def kind(name):
        cls = getattr(pm, name, None)
        return cls is not None and isinstance(error, cls)
    if kind("EmptySelectionError"):
        return "no faces selected: select the feature's faces in Edit Mode (face select) first"
    if kind("WholeMeshSelectedError"):
        return ("the whole mesh is selected: select only the feature (e.g. a boss and a ring "
                "of surface around it), not every face")
    if kind("SelectionTopologyError"):
        return (f"the selected faces must be one patch shaped like a disc or a ring, without "
                f"handles ({error}): select one connected feature")
    if kind("TargetTooSmallError"):
        return (f"the feature does not fit there ({error}): paste it on a larger part of the "
                "surface, scale it down or lower the blend radius")
    return None
