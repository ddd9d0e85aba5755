"""The fuzz table: one entry per public callable of paramorph_native, each a
generator of plausible and mutated arguments (DESIGN.md §3: every entry point
validates its input and raises a typed error; it never crashes).

TABLE maps a name ("sphere_map", "PasteSession", "PasteSession.update") to
gen(g) -> (args, kwargs), where g is a Gen (a seeded RNG with helpers for
meshes, index arrays and options). A new public function is one entry here;
tests/fuzz/test_fuzz.py fails while one is missing. Classes the module only
returns (results) are listed in RESULT_TYPES; exception classes in
TYPED_ERRORS (what a call may raise on bad input) or UNTYPED_ERRORS.
"""
import math
import os
import sys
from pathlib import Path

import numpy as np

from specs import Apply, Call, Callback, MUTATIONS, describe  # noqa: F401

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "native"))
import meshes  # noqa: E402  (tests/native/meshes.py: the shared mesh families)

# Exception classes of the module. A call refusing bad input with one of
# TYPED_ERRORS (or a subclass) is a valid outcome; Cancelled is valid when the
# callback asked to stop; ComputeError is valid only for an OpenCL failure,
# which is its subclass DeviceError.
TYPED_ERRORS = ("MeshError", "NotClosedError", "NotOpenError", "NotGenusZeroError",
                "DisconnectedError", "NonManifoldError", "DegenerateFaceError",
                "InvalidInputError", "ConstraintError", "TargetTooSmallError",
                "EmptySelectionError", "WholeMeshSelectedError", "SelectionTopologyError")
UNTYPED_ERRORS = ("Cancelled", "ComputeError", "DeviceError")

# Findings already known and being fixed elsewhere: reported as known, they do
# not fail a run. Each: (target, error type, regular expression the message
# must match, why). Remove an entry when its fix lands; a stale one fails the
# driver's tests only if the target disappears.
KNOWN_FINDINGS = ()  # (function, error type, message regex, why): none open

# Classes the module returns but that Python cannot construct (no __init__):
# their methods are still fuzzed, through entries "Class.method" below.
RESULT_TYPES = ("AlignedSphereMap", "FitToSurface", "BalancedSphereMap", "ProgressiveSphereMap", "CorrespondenceCandidate",
                "ExtremityTips", "Feature", "FeatureMatch", "FeaturePoints", "ProtrusionTips",
                "IsometricSphereMap", "MapDistortion", "MergedTopology", "MeshReport", "Morph",
                "MorphCorrespondence", "OptimizedSphereMap", "OverlayStats", "PlanarMap",
                "RefinedRegion", "RegionGraph", "RepairReport", "RepairResult", "Segmentation", "SelfIntersections",
                "SphereFlow", "SphereMap", "SurfaceDistance", "WeldStats")

NAN, INF = float("nan"), float("inf")

# Keyword options that bound the work a call does (iterations, steps, rings): a
# huge value makes a long run the caller asked for, so a timeout with one over
# 1e5 is reported apart ("slow_budget"), not as a hang.
BUDGET_OPTIONS = ("rounds", "max_iterations", "max_steps", "steps", "max_rings", "max_outer_iterations", "samples",
                  "smooth_pleats")


def public_callables(module):
    """Every public callable of the module the table must cover: functions, the
    constructors of classes that have one, and every method of every class
    (class attributes that are callable and not properties). Exceptions and
    result types are checked against their explicit lists by the test."""
    names = set()
    for name in dir(module):
        if name.startswith("_"):
            continue
        obj = getattr(module, name)
        if isinstance(obj, type):
            if issubclass(obj, BaseException):
                continue
            if name not in RESULT_TYPES:
                names.add(name)
            for attr, value in vars(obj).items():
                if attr.startswith("_") or isinstance(value, property):
                    continue
                if callable(value) or isinstance(value, (staticmethod, classmethod)):
                    names.add(f"{name}.{attr}")
        elif callable(obj):
            names.add(name)
    return names


# --- meshes ----------------------------------------------------------------------

def _tetrahedron():
    return (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float),
            np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], np.int32))


def _bipyramid():
    return (np.array([[1, 0, 0], [-0.5, 0.8, 0], [-0.5, -0.8, 0], [0, 0, 1], [0, 0, -1]], float),
            np.array([[0, 1, 3], [1, 2, 3], [2, 0, 3], [1, 0, 4], [2, 1, 4], [0, 2, 4]], np.int32))


def _octahedron():
    return (np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float),
            np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5],
                      [3, 1, 5], [0, 3, 5]], np.int32))


def _pillow():
    """Two faces on the same three vertices, opposite orientations."""
    return np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), np.array([[0, 1, 2], [0, 2, 1]], np.int32)


def _triangle():
    return np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), np.array([[0, 1, 2]], np.int32)


def _quad():
    return (np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float),
            np.array([[0, 1, 2], [0, 2, 3]], np.int32))


def _cap_removed(subdivisions, height):
    V, F = meshes.icosphere(subdivisions)
    keep = V[F].mean(axis=1)[:, 2] < height
    return meshes._compact(V, F[keep])


def _annulus():
    V, F = meshes.icosphere(2)
    z = V[F].mean(axis=1)[:, 2]
    return meshes._compact(V, F[np.abs(z) < 0.5])


def _one_face_hole():
    V, F = meshes.icosphere(1)
    return V, F[1:].copy()


def _duplicate_face():
    V, F = meshes.icosphere(1)
    return V, np.vstack([F, F[:1]]).astype(np.int32)


def _repeated_index():
    V, F = meshes.icosphere(1)
    F = F.copy()
    F[3, 2] = F[3, 0]
    return V, F


def _bump_plane():
    V, F, _ = meshes.bump_plane(n=10, height=0.1, sigma=0.3, radius=0.6)
    return V, F


CLOSED = {
    "tetrahedron": _tetrahedron, "bipyramid": _bipyramid, "octahedron": _octahedron,
    "icosahedron": lambda: meshes.icosphere(0), "icosphere1": lambda: meshes.icosphere(1),
    "icosphere2": lambda: meshes.icosphere(2), "cube": lambda: meshes.box(cells=1),
    "box2": lambda: meshes.box(cells=2), "blob1": lambda: meshes.noisy_blob(1),
    "octopus1": lambda: meshes.coarse_octopus(1), "cad_box2": lambda: meshes.cad_box(2),
}
OPEN = {
    "triangle": _triangle, "quad": _quad, "open_disc": meshes.open_disc,
    "plane4": lambda: meshes.plane_grid(4), "plane8": lambda: meshes.plane_grid(8),
    "bump_plane": _bump_plane, "one_face_hole": _one_face_hole,
    "hemisphere": lambda: _cap_removed(1, 0.0), "annulus": _annulus,
}
BROKEN = {
    "pillow": _pillow, "torus": lambda: meshes.torus(8, 4), "two_spheres": meshes.two_spheres,
    "non_manifold_edge": meshes.non_manifold_edge, "pinched_spheres": meshes.pinched_spheres,
    "flipped_face": meshes.flipped_face, "loose_vertex": meshes.loose_vertex,
    "zero_area_face": meshes.zero_area_face, "duplicate_face": _duplicate_face,
    "repeated_index": _repeated_index,
}
_CACHE = {}


def base_mesh(name):
    if name not in _CACHE:
        for table in (CLOSED, OPEN, BROKEN):
            if name in table:
                V, F = table[name]()
                _CACHE[name] = (np.ascontiguousarray(V, np.float64), np.ascontiguousarray(F, np.int32))
    V, F = _CACHE[name]
    return V.copy(), F.copy()


# Mutations of V (coordinates) and F (indices) that keep the mesh "a mesh",
# and those that break the array itself.
V_VALUE_MUTATIONS = ["nan", "inf", "neg_inf", "huge", "tiny", "denormal", "scale_1e200",
                     "scale_1e-200", "scale_1e150", "scale_1e-150", "scale_neg", "zeros"]
V_ARRAY_MUTATIONS = ["strided", "fortran", "drop_row", "add_row", "empty", "transpose", "flatten",
                     "add_axis", "float32", "float16", "int32", "bool", "complex", "object", "str",
                     "list"]
F_VALUE_MUTATIONS = ["index_minus1", "index_huge", "index_2e40", "index_big", "index_min",
                     "drop_row", "add_row", "shuffle", "swap_columns", "zeros"]
F_ARRAY_MUTATIONS = ["strided", "fortran", "empty", "transpose", "flatten", "add_axis", "int64",
                     "uint32", "int16", "int8", "float64", "float32", "bool", "object", "str", "list"]


class Mesh:
    """A generated mesh: V, F as passed (maybe mutated), V0, F0 the clean base
    (for arrays sized by the mesh), name and the mutations applied."""

    def __init__(self, name, V, F, V0, F0, labels):
        self.name, self.V, self.F, self.V0, self.F0, self.labels = name, V, F, V0, F0, labels

    @property
    def n(self):
        return len(self.V0)

    @property
    def m(self):
        return len(self.F0)


class Gen:
    """Seeded choices for one case. p_mut is the chance each argument or option is
    mutated (0 for a case of plausible inputs only)."""

    def __init__(self, rng):
        self.rng = rng
        self.p_mut = float(rng.choice([0.0, 0.1, 0.25, 0.5], p=[0.3, 0.3, 0.25, 0.15]))
        self.notes = []

    # small helpers
    def choice(self, seq):
        return seq[int(self.rng.integers(len(seq)))]

    def chance(self, p):
        return bool(self.rng.random() < p)

    def mutate(self):
        return self.chance(self.p_mut)

    def u(self):
        return float(self.rng.random())

    def note(self, text):
        self.notes.append(text)

    # meshes
    def mesh(self, prefer="closed", tag="mesh"):
        r = self.rng.random()
        if prefer == "closed":
            family = CLOSED if r < 0.75 else (OPEN if r < 0.85 else BROKEN)
        elif prefer == "open":
            family = OPEN if r < 0.75 else (CLOSED if r < 0.85 else BROKEN)
        else:
            family = CLOSED if r < 0.4 else (OPEN if r < 0.75 else BROKEN)
        name = self.choice(sorted(family))
        V0, F0 = base_mesh(name)
        V, F, labels = V0.copy(), F0.copy(), [name]
        if self.chance(0.15):  # a plausible variation: noise, scale, rotation, int64 faces
            kind = self.choice(["noise", "scale", "int64", "float32", "shift"])
            if kind == "noise":
                V = V + 1e-3 * self.rng.standard_normal(V.shape)
            elif kind == "scale":
                V = V * 10.0 ** self.rng.integers(-6, 7)
            elif kind == "int64":
                F = F.astype(np.int64)
            elif kind == "float32":
                V = V.astype(np.float32)
            else:
                V = V + 1e3 * self.rng.standard_normal(3)
            labels.append(kind)
        if self.mutate():
            op = self.choice(V_VALUE_MUTATIONS if self.chance(0.6) else V_ARRAY_MUTATIONS)
            V = MUTATIONS[op](V, self.u())
            labels.append("V:" + op)
        if self.mutate():
            op = self.choice(F_VALUE_MUTATIONS if self.chance(0.6) else F_ARRAY_MUTATIONS)
            F = MUTATIONS[op](F, self.u())
            labels.append("F:" + op)
        if self.chance(self.p_mut * 0.1):
            V, F = (None, F) if self.chance(0.5) else (V, None)
            labels.append("None")
        self.note(f"{tag}={'+'.join(labels)}")
        return Mesh(name, V, F, V0, F0, labels)

    # arrays derived from a mesh
    def array(self, a, tag, value_ops=None, array_ops=None):
        """a, or with chance p_mut one of its mutations (a may be a spec: the
        mutation is then applied in the child)."""
        if not self.mutate():
            return a
        ops = (value_ops or V_VALUE_MUTATIONS) if self.chance(0.6) else (array_ops or V_ARRAY_MUTATIONS)
        op = self.choice(ops)
        self.note(f"{tag}:{op}")
        if isinstance(a, np.ndarray):
            return MUTATIONS[op](a, self.u())
        return Apply(op, a, self.u())

    def indices(self, count, k, tag, unique=True, allow_empty=False):
        """k indices below count (int32 or int64), or a mutation of them."""
        k = max(0 if allow_empty else 1, min(k, count))
        idx = np.sort(self.rng.choice(count, size=k, replace=False)) if unique and count else \
            self.rng.integers(0, max(count, 1), size=k)
        idx = idx.astype(self.choice([np.int32, np.int64]))
        if self.mutate():
            op = self.choice(["index_minus1", "index_huge", "index_2e40", "index_big", "index_min",
                              "empty", "add_row", "float64", "bool", "add_axis", "list", "strided",
                              "duplicate", "all", "uint32", "str", "none"])
            self.note(f"{tag}:{op}")
            if op == "duplicate":
                return np.concatenate([idx, idx[:1]]) if len(idx) else idx
            if op == "all":
                return np.arange(count, dtype=np.int32)
            if op == "none":
                return None
            return MUTATIONS[op](idx, self.u())
        return idx

    def sphere_of(self, mesh, tag="sphere"):
        """A sphere map for a mesh: the sphere_map result (child), or the clean vertices
        centred and projected (parent), then maybe mutated."""
        if self.chance(0.5):
            X = Call("sphere_map", (mesh.V0, mesh.F0), {"backend": "cpu"}, attr="positions")
        else:
            X = mesh.V0 - mesh.V0.mean(axis=0)
            norms = np.linalg.norm(X, axis=1, keepdims=True)
            X = X / np.where(norms > 0, norms, 1.0)
        return self.array(X, tag)

    def unit_points(self, k, tag="points"):
        P = self.rng.standard_normal((max(k, 1), 3))
        P /= np.linalg.norm(P, axis=1, keepdims=True)
        return self.array(P, tag)

    def points(self, k, cols=3, tag="points", scale=1.0):
        return self.array(scale * self.rng.standard_normal((k, cols)), tag)

    # options
    def options(self, spec):
        """kwargs from spec {name: kind}: each option omitted, plausible or (chance
        p_mut) a mutated value of its kind. A huge iteration budget makes a call
        run to the time limit, so budgets get one only now and then."""
        out = {}
        for name, kind in spec.items():
            mutated = self.mutate()
            if not mutated and self.chance(0.5):
                continue
            value = bad_value(self, kind) if mutated else good_value(self, kind)
            while name in BUDGET_OPTIONS and isinstance(value, int) and value > 10 ** 5 and self.chance(0.8):
                value = bad_value(self, kind)
            if mutated:
                self.note(f"{name}={describe(value)}")
            out[name] = value
        return out


# Option kinds: ("float", lo, hi), ("int", lo, hi), ("bool",), ("enum", choices),
# ("progress",), ("const", value) (a non-option keyword that must be there).
def good_value(g, kind):
    tag = kind[0]
    if tag == "float":
        lo, hi = kind[1], kind[2]
        if lo > 0 and hi / lo > 100:
            return float(math.exp(g.rng.uniform(math.log(lo), math.log(hi))))
        return float(g.rng.uniform(lo, hi))
    if tag == "int":
        return int(g.rng.integers(kind[1], kind[2] + 1))
    if tag == "bool":
        return bool(g.chance(0.5))
    if tag == "enum":
        return g.choice(kind[1])
    if tag == "progress":
        k = g.choice(["true", "none", "true", "after"])
        return Callback(k, int(g.rng.integers(0, 4)))
    if tag == "const":
        return kind[1]
    raise ValueError(kind)


BAD_FLOATS = [NAN, INF, -INF, -1.0, 0.0, -0.0, 1e300, -1e300, 1e-300, 5e-324, 2.0 ** 63, 1e20,
              "1.0", None, [1.0], np.float32(NAN), True, 1j, np.array([1.0, 2.0]), np.float64(-5.0)]
BAD_INTS = [0, -1, -2 ** 31, 2 ** 31 - 1, 2 ** 31, 2 ** 63, -2 ** 63, 1.5, NAN, None, "3", True,
            np.int64(2 ** 40), np.int64(-7), [1], 10 ** 6, 10 ** 9]
BAD_BOOLS = [None, 2, "yes", np.bool_(True), 0.5, [], np.array([True, False])]
BAD_ENUMS = ["", "AUTO", "cpu\x00x", "x" * 10000, None, 3, b"cpu", "opencl ", "auto\n"]
BAD_CALLBACKS = ["false", "after", "raise", "no_truth", "bad_bool", "nan", "string", "wrong_arity"]


def bad_value(g, kind):
    tag = kind[0]
    if tag == "float":
        return g.choice(BAD_FLOATS)
    if tag == "int":
        return g.choice(BAD_INTS)
    if tag == "bool":
        return g.choice(BAD_BOOLS)
    if tag == "enum":
        return g.choice(BAD_ENUMS + (["opencl"] if "opencl" in kind[1] else []))
    if tag == "progress":
        r = g.rng.random()
        if r < 0.8:
            return Callback(g.choice(BAD_CALLBACKS), int(g.rng.integers(0, 6)))
        return g.choice([5, "progress", np.zeros(3), print])
    if tag == "const":
        return g.choice(BAD_FLOATS + BAD_INTS)
    raise ValueError(kind)


PROGRESS = ("progress",)
BACKEND = ("enum", ["auto", "cpu", "opencl"])
CARRY = ("enum", ["auto", "always", "never"])


# --- the table ----------------------------------------------------------------------

def _mesh_only(prefer, options):
    def gen(g):
        m = g.mesh(prefer)
        return (m.V, m.F), g.options(options)
    return gen


def _no_args(g):
    if g.mutate():
        g.note("extra argument")
        return (g.choice([1, None, "x", np.zeros(3)]),), {}
    return (), {}


def gen_sphere_map(g):
    m = g.mesh("closed")
    return (m.V, m.F), g.options({
        "weights": ("enum", ["conformal", "barycentric"]), "tol": ("float", 1e-12, 1e-2),
        "max_iterations": ("int", 1, 5000), "solver": ("enum", ["auto", "pcg", "cholesky", "jacobi"]),
        "backend": BACKEND, "progress": PROGRESS, "max_outer_iterations": ("int", 0, 8),
        "outer_tol": ("float", 1e-8, 1e-1),
        "init": ("enum", ["auto", "stereographic", "relaxation", "progressive"]),
        "check_every": ("int", 1, 100), "omega": ("float", 0.1, 1.5), "reorder": ("bool",)})


def gen_isometric_map(g):
    m = g.mesh("open")
    kw = g.options({"soft_weight": ("float", 1e-3, 1e4), "max_iterations": ("int", 0, 300),
                    "tol": ("float", 1e-10, 1e-2), "backend": BACKEND, "allow_folds": ("bool",),
                    "progress": PROGRESS})
    if g.chance(0.4):
        k = int(g.rng.integers(1, 5))
        kw["pinned"] = g.indices(m.n, k, "pinned")
        kw["pinned_uv"] = g.points(k, 2, "pinned_uv")
    if g.chance(0.25):
        k = int(g.rng.integers(1, 5))
        kw["soft"] = g.indices(m.n, k, "soft")
        kw["soft_uv"] = g.points(k, 2, "soft_uv")
    if g.chance(0.3):
        kw["init"] = g.choice(["auto", "tutte", "free"]) if g.chance(0.5) else g.points(m.n, 2, "init")
        if g.mutate():
            kw["init"] = g.choice(BAD_ENUMS + [np.zeros((m.n, 3)), np.full((m.n, 2), NAN)])
            g.note(f"init={describe(kw['init'])}")
    return (m.V, m.F), kw


def gen_concavity(g):
    m = g.mesh("any")
    return (m.V, m.F), {}


def gen_shape_signature(g):
    m = g.mesh("closed")
    kw = g.options({"bins": ("int", 1, 64), "log_range": ("float", 0.5, 8.0), "progress": PROGRESS})
    if g.chance(0.3):
        kw["sphere"] = g.sphere_of(m)
    return (m.V, m.F), kw


def gen_signature_distance(g):
    bins = int(g.rng.integers(1, 40))
    a = g.rng.random(bins)
    b = g.rng.random(bins if not g.mutate() else int(g.rng.integers(0, 40)))
    a, b = a / max(a.sum(), 1e-300), b / max(b.sum(), 1e-300)
    return (g.array(a, "a"), g.array(b, "b")), g.options({"log_range": ("float", 0.5, 8.0)})


def gen_area_stretch(g):
    m = g.mesh("closed")
    return (m.V, m.F, g.sphere_of(m)), {}


def gen_segment_extremities(g):
    m = g.mesh("closed")
    kw = g.options({"threshold": ("float", 0.1, 5.0), "min_area": ("float", 1e-4, 0.5),
                    "progress": PROGRESS})
    if g.chance(0.3):
        kw["sphere"] = g.sphere_of(m)
    return (m.V, m.F), kw


def gen_feature_regions(g):
    m = g.mesh("any")
    kw = g.options({"normal_angle": ("float", 1.0, 179.0), "concavity_threshold": ("float", 1e-4, 0.5),
                    "min_area": ("float", 1e-4, 0.5), "progress": PROGRESS})
    if g.chance(0.3):
        kw["concavity"] = g.array(Call("concavity", (m.V0, m.F0)), "concavity")
    return (m.V, m.F), kw


def gen_feature_points(g):
    m = g.mesh("any")
    if g.chance(0.5):
        labels = Call("feature_regions", (m.V0, m.F0), attr="face_labels")
    else:
        labels = g.rng.integers(0, 4, size=m.m).astype(np.int32)
    labels = g.array(labels, "face_labels", F_VALUE_MUTATIONS, F_ARRAY_MUTATIONS)
    conc = g.array(Call("concavity", (m.V0, m.F0)), "concavity")
    return (m.V, m.F, labels, conc), g.options({"spacing": ("float", 1e-3, 0.5)})


def _segmentation(g, m, tag="segmentation"):
    """A Segmentation of m, or (mutated) of another mesh, or not a Segmentation."""
    V0, F0 = m.V0, m.F0
    if g.mutate():
        other = g.mesh("closed", tag=tag + "_of")
        V0, F0 = other.V0, other.F0
        g.note(f"{tag} of another mesh")
        if g.chance(0.2):
            return g.choice([None, 3, np.zeros(3), Call("validate", (V0, F0))])
    if g.chance(0.5):
        return Call("segment_extremities", (V0, F0))
    return Call("feature_regions", (V0, F0))


def gen_extremity_tips(g):
    m = g.mesh("closed")
    return (m.V, m.F, _segmentation(g, m)), g.options({"prominence": ("float", 0.0, 0.5)})


def gen_protrusion_tips(g):
    m = g.mesh("closed")
    return (m.V, m.F), g.options({"radius": ("float", 1e-3, 2.0), "samples": ("int", 1, 300),
                                  "max_tips": ("int", 0, 50)})


def gen_region_graph(g):
    m = g.mesh("closed")
    return (m.V, m.F, _segmentation(g, m)), g.options({"long_edge_factor": ("float", 0.1, 10.0)})


MATCH_OPTIONS = {"normal_angle": ("float", 1.0, 179.0), "concavity_threshold": ("float", 1e-4, 0.5),
                 "min_area": ("float", 1e-4, 0.5), "spacing": ("float", 1e-3, 0.5),
                 "long_edge_factor": ("float", 0.1, 10.0), "alignment_nodes": ("int", 1, 10),
                 "max_region_score": ("float", 0.01, 5.0), "outlier_factor": ("float", 0.5, 10.0),
                 "max_point_distance": ("float", 1e-3, 1.0), "progress": PROGRESS}


def gen_match_features(g):
    a, b = g.mesh("closed", "A"), g.mesh("closed", "B")
    return (a.V, a.F, b.V, b.F), g.options(MATCH_OPTIONS)


def _pairs(g, a, b, tag):
    k = int(g.rng.integers(1, 4))
    P = np.stack([g.rng.integers(0, a.n, k), g.rng.integers(0, b.n, k)], 1).astype(np.int32)
    if g.mutate():
        op = g.choice(["index_minus1", "index_huge", "index_big", "empty", "transpose", "flatten",
                       "float64", "str", "list", "add_row", "strided"])
        g.note(f"{tag}:{op}")
        P = MUTATIONS[op](P, g.u())
    return P


MORPH_OPTIONS = {"automatic": ("bool",), "proxy_faces": ("int", 4, 400), "extremities": ("bool",),
                 "registration": ("bool",), "features": ("bool",), "progress": PROGRESS}


def _with_pins_and_pairs(g, a, b, kw):
    """The morph calls' arguments, sometimes with pins and given pairs."""
    if g.chance(0.3):
        kw["pins"] = _pairs(g, a, b, "pins")
    if g.chance(0.2):
        kw["pairs"] = _pairs(g, a, b, "pairs")
    return (a.V, a.F, b.V, b.F), kw


def gen_morph(g):
    a, b = g.mesh("closed", "A"), g.mesh("closed", "B")
    kw = g.options(dict(MORPH_OPTIONS, merge_tolerance=("float", 1e-9, 1e-3),
                        weld_tolerance=("float", 0.0, 1e-3)))
    return _with_pins_and_pairs(g, a, b, kw)


def gen_morph_correspondence(g):
    a, b = g.mesh("closed", "A"), g.mesh("closed", "B")
    kw = g.options(MORPH_OPTIONS)
    return _with_pins_and_pairs(g, a, b, kw)


def gen_optimize_sphere_map(g):
    m = g.mesh("closed")
    kw = g.options({"epsilon": ("float", 1e-4, 0.9), "max_iterations": ("int", 0, 50),
                    "tol": ("float", 1e-10, 1e-2), "solver": ("enum", ["auto", "barrier", "ipopt"]),
                    "progress": PROGRESS})
    args = (m.V, m.F)
    if g.chance(0.6):
        args = args + (g.sphere_of(m),)
    if g.chance(0.2):
        kw["target"] = g.array(m.V0 * 1.1, "target")
    if g.chance(0.2):
        kw["weights"] = g.array(g.rng.random(m.n) + 0.1, "weights")
    return args, kw


def gen_align_sphere_map(g):
    m = g.mesh("closed")
    k = int(g.rng.integers(1, min(m.n, 4) + 1))
    vertices = g.indices(m.n, k, "vertices")
    targets = g.unit_points(k, "targets")
    args = [m.V, m.F, g.sphere_of(m), vertices, targets]
    if g.chance(0.3):
        args.append(g.array(g.rng.random(k) + 0.1, "weights"))
    kw = g.options({"epsilon": ("float", 1e-4, 0.9), "max_iterations": ("int", 0, 50),
                    "tol": ("float", 1e-10, 1e-2), "feature_weight": ("float", 0.0, 500.0),
                    "warp_width": ("float", 0.0, 2.0), "solver": ("enum", ["auto", "barrier", "ipopt"]),
                    "progress": PROGRESS})
    if g.chance(0.2):
        kw["target"] = g.array(m.V0 * 1.1, "target")
    return tuple(args), kw


def gen_map_distortion(g):
    a, b = g.mesh("closed", "A"), g.mesh("closed", "B")
    return ((a.V, a.F, g.sphere_of(a, "sphere_a"), b.V, b.F, g.sphere_of(b, "sphere_b")),
            g.options({"cap": ("float", 0.5, 50.0)}))


def gen_flow_sphere_map(g):
    m = g.mesh("closed")
    p = int(g.rng.integers(1, 5))
    X = g.sphere_of(m, "X")
    from_points = g.unit_points(p, "from")
    if g.chance(0.5):
        to_points = g.array(from_points + 0.05 * g.rng.standard_normal(from_points.shape)
                            if isinstance(from_points, np.ndarray) and from_points.ndim == 2
                            and from_points.dtype.kind == "f" else from_points, "to")
    else:
        to_points = g.unit_points(p, "to")
    pinned = g.indices(m.n, int(g.rng.integers(0, p + 1)), "pinned", allow_empty=True)
    return (m.F, X, from_points, to_points, pinned), {}


def gen_untangle_sphere_map(g):
    m = g.mesh("closed")
    X = g.sphere_of(m, "X")
    if g.chance(0.4):  # fold it: swap two rows of a clean map
        X = Apply("shuffle", X, g.u()) if not isinstance(X, np.ndarray) else MUTATIONS["shuffle"](X, g.u())
        g.note("X shuffled")
    fixed = g.indices(m.n, int(g.rng.integers(0, 4)), "fixed", allow_empty=True)
    return (m.V, m.F, X, fixed), g.options({"max_rings": ("int", 0, 20)})


def gen_warp_sphere_points(g):
    p = int(g.rng.integers(1, 30))
    k = int(g.rng.integers(1, 5))
    frm = g.unit_points(k, "from")
    to = g.unit_points(k, "to") if g.chance(0.5) else frm
    return (g.unit_points(p, "points"), frm, to), g.options({"steps": ("int", 1, 64)})


def gen_carry_through_maps(g):
    m = g.mesh("closed")
    return (m.V, m.F, g.sphere_of(m, "sphere_a"), g.unit_points(int(g.rng.integers(1, 20)))), {}


def gen_map_through_proxy(g):
    m = g.mesh("closed")
    if g.chance(0.5):
        proxy = g.mesh("closed", "proxy")
        pV, pF, pmap = proxy.V, proxy.F, g.sphere_of(proxy, "proxy_map")
    else:
        pV, pF, pmap = m.V0, m.F0, g.sphere_of(m, "proxy_map")
    return (m.V, pV, pF, pmap), {}


def gen_balanced_sphere_map(g):
    m = g.mesh("closed")
    return (m.V, m.F), g.options({"level_ratio": ("float", 1.1, 16.0), "max_steps": ("int", 0, 60),
                                  "polish_face_steps": ("float", 0.0, 1e6), "progress": PROGRESS})


def gen_progressive_sphere_map(g):
    m = g.mesh("closed")
    return (m.V, m.F), g.options({"level_ratio": ("float", 1.01, 16.0), "level_work": ("float", 0.0, 1e6),
                                  "min_sweeps": ("int", 0, 10), "max_sweeps": ("int", 0, 100),
                                  "insert_steps": ("int", 0, 10), "progress": PROGRESS})


def gen_isometric_sphere_map(g):
    m = g.mesh("closed")
    start = g.sphere_of(m, "start")
    return (m.V, m.F, start), g.options({"max_steps": ("int", 0, 60), "tol": ("float", 1e-10, 1e-2),
                                         "progress": PROGRESS})


def gen_overlay(g):
    a, b = g.mesh("closed", "A"), g.mesh("closed", "B")
    return ((g.sphere_of(a, "sphere_a"), a.F, g.sphere_of(b, "sphere_b"), b.F),
            g.options({"merge_tolerance": ("float", 1e-12, 1e-2), "progress": PROGRESS}))


def gen_simplify(g):
    m = g.mesh("closed")
    target = int(g.rng.integers(4, max(5, m.m)))
    if g.mutate():
        target = g.choice([0, 1, 2, 3, -1, m.m, m.m * 10, 2 ** 31 - 1, 2 ** 31, 1.5, None])
        g.note(f"target_faces={target!r}")
    return (m.V, m.F, target), {}


def gen_self_intersections(g):
    m = g.mesh("any")
    return (m.V, m.F), {}


def gen_surface_distance(g):
    a, b = g.mesh("any", "A"), g.mesh("any", "B")
    return (a.V, a.F, b.V, b.F), g.options({"progress": PROGRESS})


def _feature_source(g):
    """A surface and a disc-like selection of its faces (a cap around a vertex), or a
    mutated selection (empty, every face, two caps, out of range ...)."""
    m = g.mesh(g.choice(["open", "closed"]), "source")
    C = m.V0[m.F0].mean(axis=1)
    centre = m.V0[int(g.rng.integers(m.n))]
    d = np.linalg.norm(C - centre, axis=1)
    k = max(1, int(len(d) * g.rng.uniform(0.05, 0.5)))
    faces = np.sort(np.argsort(d)[:k]).astype(np.int32)
    if g.mutate():
        op = g.choice(["empty", "all", "two_caps", "ring", "index_minus1", "index_huge", "add_row",
                       "float64", "add_axis", "list", "strided"])
        g.note(f"feature_faces:{op}")
        if op == "all":
            faces = np.arange(m.m, dtype=np.int32)
        elif op == "two_caps":
            faces = np.union1d(faces, np.argsort(-d)[:k]).astype(np.int32)
        elif op == "ring":
            faces = np.sort(np.argsort(d)[k // 2:k]).astype(np.int32)
        else:
            faces = MUTATIONS[op](faces, g.u())
    return m, faces


def gen_extract_feature(g):
    m, faces = _feature_source(g)
    return (m.V, m.F, faces), g.options({"resolution": ("int", 2, 64), "carry": CARRY, "backend": BACKEND,
                                         "progress": PROGRESS})


def _clean_feature(g):
    """A Feature built in the child from a bump on a plane (always extractable),
    now and then carried as its own mesh (pasted sewn in)."""
    V, F, faces = meshes.bump_plane(n=int(g.rng.integers(8, 16)), height=0.1, sigma=0.3, radius=0.6)
    return Call("extract_feature", (V, F, faces), {"resolution": int(g.rng.integers(4, 24)),
                                                   "carry": "always" if g.chance(0.3) else "auto",
                                                   "backend": "cpu"})


def _feature(g):
    if g.chance(0.7):
        return _clean_feature(g)
    m, faces = _feature_source(g)
    return Call("extract_feature", (m.V0, m.F0, faces), {"resolution": 8, "backend": "cpu"})


def gen_sample_feature(g):
    f = _feature(g)
    if g.mutate():
        f = g.choice([None, 3, Call("validate", _tetrahedron())])
        g.note("feature not a Feature")
    uv = g.points(int(g.rng.integers(0, 20)), 2, "uv", scale=0.5)
    return (f, uv), {}


def gen_feature_to_arrays(g):
    return (_feature(g),), {}


def gen_feature_from_arrays(g):
    f = _clean_feature(g)
    d = Call(f.target, f.args, f.kwargs, method="to_arrays")
    if g.chance(max(g.p_mut, 0.2) * 2):
        op = g.choice(["delete", "none", "scalar", "string", "extra"] + V_VALUE_MUTATIONS + V_ARRAY_MUTATIONS
                      + ["index_minus1", "index_huge", "drop_row", "add_row"])
        d = Apply("dict", d, g.u(), op, g.u())
        g.note(f"arrays:{op}")
    if g.chance(g.p_mut * 0.2):
        d = g.choice([None, {}, {"faces": None}, [1, 2]])
        g.note("not a dict")
    return (d,), {}


def gen_refine_region(g):
    m = g.mesh("any")
    faces = g.indices(m.m, int(g.rng.integers(1, max(2, m.m // 3))), "region_faces")
    return (m.V, m.F, faces), g.options({"level": ("int", 0, 3), "progress": PROGRESS})


def _rbf_centres(g):
    k = int(g.rng.integers(1, 30))
    return g.points(k, 3, "centres")


RBF_OPTIONS = {"basis": ("enum", ["polyharmonic", "wendland"]), "polynomial_degree": ("int", -1, 2),
               "support_radius": ("float", 0.0, 3.0)}


def gen_rbf(g):
    return (_rbf_centres(g),), g.options(RBF_OPTIONS)


def _rbf(g):
    centres = g.rng.standard_normal((int(g.rng.integers(1, 30)), 3))
    kw = g.options(RBF_OPTIONS) if g.chance(0.3) else {}
    return centres, Call("RbfInterpolator", (centres,), kw)


def gen_rbf_solve(g):
    centres, rbf = _rbf(g)
    cols = int(g.rng.integers(1, 4))
    values = g.array(g.rng.standard_normal((len(centres), cols)), "values")
    return (rbf, values), {}


def gen_rbf_evaluate(g):
    centres, rbf = _rbf(g)
    cols = int(g.rng.integers(1, 4))
    coefficients = Call("RbfInterpolator.solve", (rbf, Apply("rbf_values", centres, cols, g.u())))
    coefficients = g.array(coefficients, "coefficients")
    return (rbf, g.points(int(g.rng.integers(0, 20)), 3, "points"), coefficients), {}


def gen_rbf_evaluation_matrix(g):
    centres, rbf = _rbf(g)
    return (rbf, g.points(int(g.rng.integers(0, 20)), 3, "points")), {}


PASTE_OPTIONS = {"rotation": ("float", -7.0, 7.0), "scale": ("float", 0.05, 3.0),
                 "blend_radius": ("float", 1.0, 4.0), "subdivision_level": ("int", -1, 3),
                 "basis": ("enum", ["polyharmonic", "wendland"]), "fit": ("enum", ["keep_form", "follow_surface"]),
                 "progress": PROGRESS}


def _paste_target(g):
    if g.chance(0.5):
        n = int(g.rng.integers(6, 14))
        V, F = meshes.plane_grid(n, half=2.0)
        return V, F, np.array([0.1, -0.2, 0.0])
    V, F = meshes.icosphere(int(g.rng.integers(1, 3)))
    return V, F, V[int(g.rng.integers(len(V)))] * 1.01


def gen_paste_session(g):
    if g.chance(0.6):
        V, F, anchor = _paste_target(g)
    else:
        m = g.mesh("any", "target")
        V, F, anchor = m.V, m.F, m.V0[int(g.rng.integers(m.n))]
    kw = g.options(PASTE_OPTIONS)
    kw["anchor"] = g.array(np.asarray(anchor, float), "anchor")
    if g.chance(g.p_mut * 0.2):
        del kw["anchor"]
        g.note("no anchor")
    feature = _feature(g) if not g.mutate() else g.choice([None, 1, _clean_feature(g)])
    return (V, F, feature), kw


def _session(g):
    V, F, anchor = _paste_target(g)
    return V, Call("PasteSession", (V, F, _clean_feature(g)), {"anchor": anchor})


def gen_paste_update(g):
    V, s = _session(g)
    kw = g.options({"rotation": ("float", -7.0, 7.0), "scale": ("float", 0.05, 3.0)})
    if g.chance(0.7):
        kw["anchor"] = g.array(V[int(g.rng.integers(len(V)))] + 0.01, "anchor")
    return (s,), kw


def gen_paste_result(g):
    V, s = _session(g)
    if g.chance(0.3):  # after an update
        s = Call("PasteSession.update", (s,), {"rotation": g.rng.uniform(-3, 3)})
        g.note("result of update() (None): TypeError expected")
    return (s,), {}


def _interpolation_args(g):
    m = g.mesh("closed")
    target = m.V0 * g.rng.uniform(0.5, 2.0) + 0.1 * g.rng.standard_normal(m.V0.shape)
    return m, m.V, g.array(target, "target")


def gen_shape_interpolation(g):
    m, source, target = _interpolation_args(g)
    return (source, target, m.F), g.options({"progress": PROGRESS})


def gen_shape_interpolation_at(g):
    m = g.mesh("closed")
    target = m.V0 * g.rng.uniform(0.5, 2.0)
    s = Call("ShapeInterpolation", (m.V0, target, m.F0))
    t = float(g.rng.uniform(-0.5, 1.5))
    if g.mutate():
        t = g.choice(BAD_FLOATS)
        g.note(f"t={describe(t)}")
    return (s, t), {}


def _parts_around(g, m, tag="part_V", clean=False):
    """Part vertices around a mesh (eyes on a head) and their labels 0..k-1
    (unless clean, maybe mutated: a label missing, out of range, too few)."""
    k = int(g.rng.integers(1, 4))
    count = int(g.rng.integers(1, 12))
    centre = m.V0.mean(axis=0)
    size = float(np.ptp(m.V0, axis=0).max()) or 1.0
    P = centre + 0.6 * size * g.rng.standard_normal((count * k, 3))
    labels = np.repeat(np.arange(k), count).astype(g.choice([np.int32, np.int64]))
    if clean:
        return P, labels
    if g.mutate():
        op = g.choice(["drop_label", "shift", "short", "negative"])
        g.note(f"part_of:{op}")
        labels = {"drop_label": lambda: np.where(labels == 0, 1 if k > 1 else 2, labels),
                  "shift": lambda: labels + 1, "short": lambda: labels[:-1],
                  "negative": lambda: labels - 1}[op]()
    return g.array(P, tag), labels


def gen_vertex_parts(g):
    m = g.mesh("any")
    vertices = m.n
    if g.mutate():
        vertices = g.choice([-1, 0, m.n - 1, 2 ** 31 - 1, 10 ** 7])
        g.note(f"vertices={vertices}")
    return (m.F, vertices), {}


def gen_signed_distance(g):
    m = g.mesh("closed")
    return (m.V, m.F, g.points(int(g.rng.integers(1, 20)))), {}


FIT_OPTIONS = {"rounds": ("int", 0, 12), "stiffness": ("float", 0.0, 10.0), "stiffness_decay": ("float", 0.01, 1.0),
               "smooth_pleats": ("int", 0, 20)}


def gen_fit_to_surface(g):
    a, b = g.mesh("closed", "A"), g.mesh("any", "B")
    held = g.indices(a.n, int(g.rng.integers(0, 4)), "held", allow_empty=True)
    return (a.V, a.F, b.V, b.F), {**g.options(FIT_OPTIONS), "held": held}


RIDE_OPTIONS = {"patch_scale": ("float", 0.1, 5.0), "min_patch": ("int", 1, 40), "attach_share": ("float", 0.0, 1.0)}


def gen_part_rider(g):
    m = g.mesh("closed", "body")
    parts, labels = _parts_around(g, m)
    return (m.V, m.F, parts, labels), g.options(RIDE_OPTIONS)


def gen_part_rider_at(g):
    m = g.mesh("closed", "body")
    parts, labels = _parts_around(g, m, clean=True)
    rider = Call("PartRider", (m.V0, m.F0, parts, labels))
    now = m.V0 * g.rng.uniform(0.1, 3.0) + g.rng.standard_normal(3)
    return (rider, g.array(now, "body_now")), {}


def _small_pair(g):
    a = base_mesh(g.choice(["octahedron", "icosahedron", "icosphere1", "cube", "blob1"]))
    b = base_mesh(g.choice(["octahedron", "icosahedron", "icosphere1", "cube", "box2"]))
    return a, b


def gen_morph_carry(g):
    (VA, FA), (VB, FB) = _small_pair(g)
    morph = Call("morph", (VA, FA, VB, FB), {"proxy_faces": 200})
    side = int(g.rng.integers(0, 2))
    F = FA if side == 0 else FB
    cols = int(g.rng.integers(1, 4))
    values = Apply("corner_values", F, cols, g.u())
    values = g.array(values, "corner_values")
    if g.mutate():
        side = g.choice([2, -1, 2 ** 31 - 1, -2 ** 31, 1.0, None, "a"])
        g.note(f"side={side!r}")
    return (morph, side, values), {}


def gen_feature_match_transform_b(g):
    (VA, FA), (VB, FB) = _small_pair(g)
    match = Call("match_features", (VA, FA, VB, FB))
    return (match, g.points(int(g.rng.integers(0, 30)), 3, "X")), {}


TABLE = {
    "align_sphere_map": gen_align_sphere_map,
    "area_stretch": gen_area_stretch,
    "balanced_sphere_map": gen_balanced_sphere_map,
    "build_info": _no_args,
    "carry_through_maps": gen_carry_through_maps,
    "concavity": gen_concavity,
    "devices": _no_args,
    "extract_feature": gen_extract_feature,
    "extremity_tips": gen_extremity_tips,
    "feature_points": gen_feature_points,
    "feature_regions": gen_feature_regions,
    "flow_sphere_map": gen_flow_sphere_map,
    "isometric_map": gen_isometric_map,
    "isometric_sphere_map": gen_isometric_sphere_map,
    "map_distortion": gen_map_distortion,
    "map_through_proxy": gen_map_through_proxy,
    "match_features": gen_match_features,
    "morph": gen_morph,
    "morph_correspondence": gen_morph_correspondence,
    "opencl_available": _no_args,
    "opencl_error": _no_args,
    "optimize_sphere_map": gen_optimize_sphere_map,
    "overlay": gen_overlay,
    "refine_region": gen_refine_region,
    "region_graph": gen_region_graph,
    "repair": _mesh_only("any", {"weld_tolerance": ("float", 0.0, 1e-2), "fill_holes": ("bool",),
                                 "orient_outward": ("bool",), "keep_largest_component": ("bool",),
                                 "progress": PROGRESS}),
    "require_closed_genus0": _mesh_only("any", {"relative_area_tolerance": ("float", 1e-16, 1e-6)}),
    "progressive_sphere_map": gen_progressive_sphere_map,
    "protrusion_tips": gen_protrusion_tips,
    "sample_feature": gen_sample_feature,
    "segment_extremities": gen_segment_extremities,
    "self_intersections": gen_self_intersections,
    "shape_signature": gen_shape_signature,
    "signature_distance": gen_signature_distance,
    "simplify": gen_simplify,
    "sphere_map": gen_sphere_map,
    "surface_distance": gen_surface_distance,
    "untangle_sphere_map": gen_untangle_sphere_map,
    "validate": _mesh_only("any", {"relative_area_tolerance": ("float", 1e-16, 1e-6)}),
    "warp_sphere_points": gen_warp_sphere_points,
    "Feature.from_arrays": gen_feature_from_arrays,
    "Feature.to_arrays": gen_feature_to_arrays,
    "FeatureMatch.transform_b": gen_feature_match_transform_b,
    "Morph.carry": gen_morph_carry,
    "PasteSession": gen_paste_session,
    "PasteSession.result": gen_paste_result,
    "PasteSession.update": gen_paste_update,
    "RbfInterpolator": gen_rbf,
    "RbfInterpolator.evaluate": gen_rbf_evaluate,
    "RbfInterpolator.evaluation_matrix": gen_rbf_evaluation_matrix,
    "RbfInterpolator.solve": gen_rbf_solve,
    "ShapeInterpolation": gen_shape_interpolation,
    "ShapeInterpolation.at": gen_shape_interpolation_at,
    "vertex_parts": gen_vertex_parts,
    "signed_distance": gen_signed_distance,
    "PartRider": gen_part_rider,
    "PartRider.at": gen_part_rider_at,
    "fit_to_surface": gen_fit_to_surface,
}


def make_case(seed, index, target):
    """The case number `index` of a run with `seed`, calling `target`: a dict that
    pickles (arrays, scalars and specs) and replays alone."""
    rng = np.random.default_rng([seed, index, sum(map(ord, target))])
    g = Gen(rng)
    args, kwargs = TABLE[target](g)
    return {"seed": seed, "index": index, "target": target, "args": tuple(args),
            "kwargs": dict(kwargs), "notes": g.notes, "p_mut": g.p_mut}


def schedule(seed, targets):
    """The order targets are fuzzed in: every target once per round, each round
    shuffled by the seed, so a short run still reaches every function."""
    targets = sorted(targets)
    rng = np.random.default_rng([seed, 7])
    round_ = 0
    while True:
        order = list(rng.permutation(len(targets)))
        for k in order:
            yield round_, targets[k]
        round_ += 1


def environment_defaults():
    """Threads the worker uses: one each (a shared two-core machine), unless set."""
    env = {}
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        env[name] = os.environ.get(name, "1")
    return env
