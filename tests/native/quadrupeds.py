"""Synthetic quadrupeds (horse-like and cow-like) with known landmark vertices,
for morph-correspondence benchmarks: the same animal re-posed and
re-tessellated, a horse against a cow.

    V, F, landmarks = quadruped("horse", faces=6000, pose=GALLOP, seed=1, jitter=0.2)

V float64 (n, 3), F int32 (m, 3), landmarks {name: vertex index} with the
names of LANDMARKS. x points forward (the head is at +x), y to the animal's
left, z up; the torso is centred on the origin, 2.7 (horse) or 2.8 (cow)
units long. The surface is one closed, 2-manifold, genus-0 triangle mesh,
oriented outwards (positive volume), with well-shaped triangles and no
self-intersection.

Construction. Every part is a swept tube: a centre line (straight segments
joined by circular arcs, so it is posable: each joint is an arc of fixed
length whose turning angle the pose sets; frames turn with the arcs)
carrying a cross-section (a superellipse with separate dorsal, ventral and
lateral semi-axes, interpolated monotonically between knots) closed by a
rounded cap with one apex vertex. The torso is such a tube along x with an
apex at each end. A limb is attached by removing the parent's faces inside
a cylinder around its root axis (a disc, checked with meshes._hole_loop),
moving the rim vertices onto the exact intersection of that cylinder with
the parent, relaxing the parent's triangles next to the rim along its exact
surface, and lofting a fillet from the rim into the tube (a Hermite curve
per azimuth, tangent to the parent at the rim and to the tube at its end).
Rings are spaced like the spacing around them (staggered, about
equilateral triangles) with as many vertices as the local perimeter needs
(consecutive rings of different counts are zipped by azimuth), so
triangles stay well shaped from the fat torso to the thin tail; the head
keeps edges of at most HEAD_EDGE so that ears and horns have a few
triangles to grow from at any resolution. Every vertex is stored as
(chain, arc length, offset in the chain's frame), so a pose re-evaluates
the same vertices.

Parts: torso; four legs (the hoof landmark is the apex of a blunt,
flat-ended cap at the bottom); neck and head in one tube (the muzzle
landmark is the apex at the front of the head, whose last arc turns it
forward); tail (its apex is the tail landmark); two ears extruded from the
head; for the cow two horns. The horse has long legs (ground to withers
about the torso's length), a slim body, a long neck rising 45 degrees and a
long bushy tail hanging down; the cow short thick legs (ground to withers
about 0.75 of its length), a deep, boxy body, a short nearly horizontal neck,
horns and a thin tail with a tuft hanging lower.

Guarantees and parameters:
  * seed changes the tessellation only (ring phases, where ring counts
    change, ring spacing), never the shape; faces changes the resolution,
    so also gives another triangulation of the same shape. The shape is
    the same up to discretisation: near each limb's root the rim follows
    the parent's triangles within a second-order error, and a feature
    smaller than about one edge (an ear at 3000 faces) is widened at its
    root to one edge length.
  * pose re-poses without changing the connectivity: for a kind, faces and
    seed every pose gives the same F and landmark indices.
  * the landmarks are apex vertices, so a name is the same anatomical
    point in every kind, pose, seed and resolution.
  * jitter in [0, 0.4]: every vertex but the landmarks moved tangentially
    by up to jitter x its local edge length and normally by ~1% of that (a
    scan-like irregular mesh; still valid: moves that would fold a face are
    halved). The jitter is applied in the rest pose and carried by the pose.

POSE_RANGES lists the angle ranges (degrees) inside which any pose is free
of self-intersections (pose_in_range checks a pose), with one condition for
the two legs of a side, which can cross under the body: front hip - hind
hip >= -20 (the front leg swung back and the hind leg swung forward by more
than 20 degrees together can collide, as real legs can in a gathered
gallop). WALK and GALLOP are presets inside them.

Also here: transform (scaled, rotated, offset or inside-out copies),
self_intersections (an exact triangle-triangle test on a grid), part
distances and mesh_stats, shared by tests and benchmarks.
"""
import functools

import numpy as np

try:
    from meshes import _hole_loop, signed_volume
except ImportError:  # pragma: no cover - imported from elsewhere than tests/native
    import os
    import sys
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from meshes import _hole_loop, signed_volume

LANDMARKS = ("hoof_fl", "hoof_fr", "hoof_hl", "hoof_hr", "muzzle", "tail")
LEGS = ("leg_fl", "leg_fr", "leg_hl", "leg_hr")
PARTS = ("torso",) + LEGS + ("neck", "tail", "ear_l", "ear_r", "horn_l", "horn_r")
ADJACENT = {frozenset(("torso", p)) for p in LEGS + ("neck", "tail")} | {
    frozenset(("neck", p)) for p in ("ear_l", "ear_r", "horn_l", "horn_r")}

# Degrees. Legs: (hip, knee); hip > 0 swings the leg forward, knee > 0 flexes
# it (front: the cannon folds backward; hind: the hock flexes, the cannon
# swings forward). neck > 0 / head > 0 raise them, tail > 0 lifts the tail.
POSE_RANGES = {"hip": (-40.0, 40.0), "knee": (0.0, 60.0), "neck": (-30.0, 30.0),
               "head": (-30.0, 30.0), "tail": (-20.0, 60.0)}
REST = {"leg_fl": (0.0, 0.0), "leg_fr": (0.0, 0.0), "leg_hl": (0.0, 0.0), "leg_hr": (0.0, 0.0),
        "neck": 0.0, "head": 0.0, "tail": 0.0}
WALK = {"leg_fl": (20.0, 10.0), "leg_fr": (-12.0, 40.0), "leg_hl": (-20.0, 0.0),
        "leg_hr": (8.0, 30.0), "neck": -12.0, "head": 8.0, "tail": 5.0}
GALLOP = {"leg_fl": (38.0, 15.0), "leg_fr": (15.0, 60.0), "leg_hl": (-38.0, 10.0),
          "leg_hr": (-10.0, 55.0), "neck": -20.0, "head": 20.0, "tail": 45.0}

LEG_CROSSING_LIMIT = -20.0   # front hip - hind hip, same side, degrees


def pose_in_range(pose):
    """True when every angle of `pose` lies in POSE_RANGES and each side's
    front hip - hind hip >= LEG_CROSSING_LIMIT (the documented, tested
    intersection-free poses)."""
    if pose is None:
        return True
    full = dict(REST)
    full.update(pose)
    for key, value in full.items():
        if key.startswith("leg_"):
            hip, knee = value
            if not (POSE_RANGES["hip"][0] <= hip <= POSE_RANGES["hip"][1]
                    and POSE_RANGES["knee"][0] <= knee <= POSE_RANGES["knee"][1]):
                return False
        elif not POSE_RANGES[key][0] <= value <= POSE_RANGES[key][1]:
            return False
    return all(full["leg_f" + s][0] - full["leg_h" + s][0] >= LEG_CROSSING_LIMIT for s in "lr")


_Y = np.array([0.0, 1.0, 0.0])
HEAD_EDGE = 0.065     # largest edge length on the head
TORSO_EDGE = 0.14     # ... and on the torso (legs ~0.4 apart need a few edges between)
MIN_FACES = 2500
_SQ3 = 0.5 * 3 ** 0.5


# --- small geometry helpers ---------------------------------------------------------

def _unit(v):
    v = np.asarray(v, np.float64)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _rotations(axis, angles):
    """Rotation matrices (..., 3, 3) about the unit `axis` by `angles` (radians)."""
    x, y, z = _unit(axis)
    K = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    a = np.asarray(angles, np.float64)[..., None, None]
    return np.eye(3) + np.sin(a) * K + (1.0 - np.cos(a)) * (K @ K)


class _Pchip:
    """Monotone C1 cubic interpolation (Fritsch-Carlson, as PCHIP; constant
    outside) of the rows of `values` (k, d) given at increasing `knots` (k,)."""

    def __init__(self, knots, values):
        x = np.asarray(knots, np.float64)
        y = np.asarray(values, np.float64).reshape(len(x), -1)
        dx = np.diff(x)[:, None]
        delta = np.diff(y, axis=0) / dx
        m = np.zeros_like(y)
        inner = delta[:-1] * delta[1:] > 0
        w1 = 2 * dx[1:] + dx[:-1]
        w2 = dx[1:] + 2 * dx[:-1]
        with np.errstate(divide="ignore", invalid="ignore"):
            harmonic = (w1 + w2) / (w1 / delta[:-1] + w2 / delta[1:])
        m[1:-1] = np.where(inner, harmonic, 0.0)
        self.x, self.y, self.m = x, y, m

    def __call__(self, s):
        x, y, m = self.x, self.y, self.m
        s = np.clip(np.asarray(s, np.float64).reshape(-1), x[0], x[-1])
        i = np.clip(np.searchsorted(x, s, side="right") - 1, 0, len(x) - 2)
        h = (x[i + 1] - x[i])[:, None]
        t = ((s - x[i]) / h[:, 0])[:, None]
        t2, t3 = t * t, t * t * t
        return ((2 * t3 - 3 * t2 + 1) * y[i] + (t3 - 2 * t2 + t) * h * m[i]
                + (3 * t2 - 2 * t3) * y[i + 1] + (t3 - t2) * h * m[i + 1])


# --- centre lines ---------------------------------------------------------------------

class _Chain:
    """A centre line from `origin` with the frame `frame` (columns N, B, T:
    T the tangent): a sequence of elements (length, axis, angle), straight
    when axis is None, else a circular arc whose tangent turns by `angle`
    (radians) about the world `axis` over `length`. The frame is carried by
    the same rotations (rotation-minimising for arcs about an axis normal
    to the tangent). eval(s) gives centres and frames at arc lengths s
    (beyond either end it continues straight)."""

    def __init__(self, origin, frame, elements):
        self.elements = [(float(L), None if a is None or abs(g) < 1e-12 else _unit(a), float(g))
                         for L, a, g in elements]
        self.starts = [0.0]
        self.origins = [np.asarray(origin, np.float64)]
        self.frames = [np.asarray(frame, np.float64)]
        for L, axis, angle in self.elements:
            C, R = self._element(len(self.starts) - 1, np.array([L]))
            self.starts.append(self.starts[-1] + L)
            self.origins.append(C[0])
            self.frames.append(R[0])
        self.length = self.starts[-1]

    def _element(self, e, s):
        p, R0 = self.origins[e], self.frames[e]
        L, axis, angle = self.elements[e] if e < len(self.elements) else (0.0, None, 0.0)
        T = R0[:, 2]
        if axis is None:
            return p + s[:, None] * T, np.broadcast_to(R0, (len(s), 3, 3))
        sc = np.clip(s, 0.0, L)
        phi = angle * sc / L
        par = (T @ axis) * axis
        perp = T - par
        radius = L / angle
        C = (p + sc[:, None] * par + radius * (np.sin(phi)[:, None] * perp
                                               + (1.0 - np.cos(phi))[:, None] * np.cross(axis, perp)))
        R = _rotations(axis, phi) @ R0
        beyond = s - sc                       # outside the arc: straight on
        return C + beyond[:, None] * R[:, :, 2], R

    def eval(self, s):
        s = np.asarray(s, np.float64).reshape(-1)
        e = np.clip(np.searchsorted(self.starts, s, side="right") - 1, 0, len(self.elements) - 1)
        C = np.empty((len(s), 3))
        R = np.empty((len(s), 3, 3))
        for k in np.unique(e):
            m = e == k
            C[m], R[m] = self._element(k, s[m] - self.starts[k])
        return C, R


def _sagittal_frame(T):
    """Frame (N, B, T) for a tangent in the x-z plane: N = T x y (dorsal side)."""
    T = _unit(T)
    N = _unit(np.cross(T, _Y))
    return np.stack([N, np.cross(T, N), T], axis=1)


# --- cross-sections -------------------------------------------------------------------

_Q = 192
_UQ = np.arange(_Q + 1) / _Q


def _section_xy(axes, expo, theta):
    """Superellipse points (N, B) at angles theta: axes (n, 3) = (dorsal,
    ventral, lateral) semi-axes, expo (n,); theta (n, m)."""
    c, s = np.cos(theta), np.sin(theta)
    p = (2.0 / expo)[:, None]
    N = np.sign(c) * np.abs(c) ** p * np.where(c > 0, axes[:, 0:1], axes[:, 1:2])
    B = np.sign(s) * np.abs(s) ** p * axes[:, 2:3]
    return N, B


def _perimeters(axes, expo):
    N, B = _section_xy(axes, expo, np.broadcast_to(-2 * np.pi * _UQ, (len(axes), _Q + 1)))
    seg = np.hypot(np.diff(N, axis=1), np.diff(B, axis=1))
    return seg.sum(axis=1), np.concatenate([np.zeros((len(axes), 1)), np.cumsum(seg, axis=1)], 1)


def _section_at(axes, expo, u):
    """Points (k, 2) of one cross-section at arc-length fractions u (k,),
    u increasing clockwise about T (theta = -2 pi u at constant speed)."""
    P, cum = _perimeters(axes[None], np.array([expo]))
    theta = -2 * np.pi * np.interp(np.mod(u, 1.0) * P[0], cum[0], _UQ)
    N, B = _section_xy(axes[None], np.array([expo]), theta[None])
    return np.stack([N[0], B[0]], axis=1)


# --- ring strips ----------------------------------------------------------------------

def _zip(A, a, B, b):
    """Faces joining ring A (below) to ring B (above). A, B vertex ids in ring
    order; a, b their parameters in [0, 1), increasing (mod 1) along the ring
    order, which runs clockwise about the tube's direction seen from outside
    (as a hole's rim runs in the faces around it). Greedy merge by parameter."""
    A, B = np.asarray(A), np.asarray(B)
    ka, kb = len(A), len(B)
    d = np.mod(b - a[0] + 0.5, 1.0) - 0.5
    j0 = int(np.argmin(np.abs(d)))
    B = np.roll(B, -j0)
    bs = np.roll(b, -j0)
    beta = d[j0] + np.mod(bs - bs[0], 1.0)
    alpha = np.mod(a - a[0], 1.0)
    keys = np.concatenate([np.append(alpha[1:], 1.0), np.append(beta[1:], beta[0] + 1.0)])
    low = np.concatenate([np.ones(ka, bool), np.zeros(kb, bool)])[np.argsort(keys, kind="stable")]
    i = np.cumsum(low) - low
    j = np.cumsum(~low) - ~low
    F = np.where(low[:, None],
                 np.stack([A[(i + 1) % ka], A[i % ka], B[j % kb]], 1),
                 np.stack([A[i % ka], B[j % kb], B[(j + 1) % kb]], 1))
    return F


def _component(F, mask, seed_face):
    """The faces of `mask` edge-connected to seed_face (empty if it is not in mask)."""
    out = np.zeros(len(F), bool)
    if not mask[seed_face]:
        return out
    ids = np.flatnonzero(mask)
    edges = {}
    for f in ids:
        for a, b in ((F[f, 0], F[f, 1]), (F[f, 1], F[f, 2]), (F[f, 2], F[f, 0])):
            edges.setdefault((min(a, b), max(a, b)), []).append(f)
    stack = [seed_face]
    out[seed_face] = True
    while stack:
        f = stack.pop()
        for a, b in ((F[f, 0], F[f, 1]), (F[f, 1], F[f, 2]), (F[f, 2], F[f, 0])):
            for g in edges[(min(a, b), max(a, b))]:
                if not out[g]:
                    out[g] = True
                    stack.append(g)
    return out


# --- the animals -----------------------------------------------------------------------

def _deg(x):
    return np.radians(x)


class _Part:
    """A tube: chain elements (a function of the pose), cross-section knots
    along the centre line and a rounded cap at the end (cap_len, cap_power).
    The torso instead shrinks along its whole length (scale) and has an apex
    at each end; `zone` is the length at each end where rings may thin out
    towards an apex."""

    def __init__(self, name, elements, knots, values, expo=2.0, cap_len=0.05, cap_power=2.0,
                 landmark=None, kmin=6, scale=None, samples=None, zone=None, hcap=None):
        self.name, self.elements = name, elements
        self.knots, self.values = np.asarray(knots, float), np.asarray(values, float)
        if self.values.ndim == 1:
            self.values = np.repeat(self.values[:, None], 3, axis=1)
        self.expo = np.broadcast_to(np.asarray(expo, float), self.knots.shape).copy()
        self._axes, self._expo = _Pchip(self.knots, self.values), _Pchip(self.knots, self.expo)
        self.cap_len, self.cap_power = cap_len, cap_power
        self.landmark, self.kmin = landmark, kmin
        self.scale, self.samples = scale, samples
        self.zone = zone
        self.hcap = hcap          # s -> largest edge target there (finer heads)

    def axes(self, s, length):
        """Semi-axes (n, 3) and exponents (n,) at centre-line positions s."""
        s = np.atleast_1d(np.asarray(s, float))
        ax, ex = self._axes(s), self._expo(s)[:, 0]
        if self.scale is not None:
            return ax * self.scale(s)[:, None], ex
        z = np.clip((s - (length - self.cap_len)) / self.cap_len, 0.0, 1.0)
        scale = np.clip(1.0 - z ** self.cap_power, 0.0, 1.0) ** (1.0 / self.cap_power)
        return ax * scale[:, None], ex

    def meridian_samples(self, s0, length, n=1500):
        """Centre-line positions from s0 to the apex, dense near the apex."""
        if self.samples is not None:
            return self.samples()
        cs = length - self.cap_len
        psi = np.linspace(0.0, 0.5 * np.pi, 240)
        cap = cs + self.cap_len * np.sin(psi) ** (2.0 / self.cap_power)
        return np.concatenate([np.linspace(s0, cs, n, endpoint=False), cap])

    def zones(self, s, length):
        """(start zone, end zone) masks: near an apex."""
        if self.zone is not None:
            return s < self.zone, s > length - self.zone
        return np.zeros(len(s), bool), s > length - self.cap_len


def _spec(kind):
    """Every dimension of one animal (units: the torso is ~2.7 long).

    Sections are (front/dorsal, back/ventral, lateral) semi-axes at knots
    along the centre line (legs: their N axis points forward, so the first
    two are the leg's front and back). Chains: straight pieces and arcs of
    fixed length; pose angles change the arcs' turning only."""
    if kind not in ("horse", "cow"):
        raise ValueError("kind must be 'horse' or 'cow'")
    S = {}
    if kind == "horse":
        a = 1.35
        S["torso"] = dict(a=a, e_len=2.6, knots=[-a, -0.9, -0.2, 0.55, 0.85, a],
                          values=[[0.47, 0.43, 0.44], [0.50, 0.50, 0.49], [0.47, 0.55, 0.47],
                                  [0.55, 0.52, 0.45], [0.58, 0.47, 0.43], [0.52, 0.42, 0.36]],
                          expo=[2.5] * 6)
        S["ground"] = -2.02
        lower = [[0.086, 0.082, 0.08], [0.066, 0.062, 0.058], [0.062, 0.06, 0.055],
                 [0.076, 0.072, 0.068], [0.058, 0.058, 0.056], [0.08, 0.076, 0.076]]
        S["legs"] = dict(
            front=dict(x=0.78, y=0.2, R=0.15, rest=(0.0, 0.0), Lf=0.17,
                       lengths=[0.24, 0.36, 0.2, 0.34, 0.1, 0.2],
                       knots=[0, 0.3, 0.55, 0.72, 0.86, 1.02, 1.3, 1.45, 1.58, 1.72],
                       values=[[0.12, 0.12, 0.1], [0.12, 0.11, 0.095], [0.09, 0.085, 0.08]] + lower
                       + lower[-1:],
                       cap=0.03),
            hind=dict(x=-0.8, y=0.225, R=0.155, rest=(-22.0, 22.0), Lf=0.2,
                      lengths=[0.26, 0.38, 0.22, 0.34, 0.1, 0.2],
                      knots=[0, 0.3, 0.58, 0.78, 0.94, 1.06, 1.36, 1.5, 1.63, 1.78],
                      values=[[0.13, 0.13, 0.105], [0.12, 0.135, 0.1], [0.085, 0.1, 0.078],
                              [0.075, 0.1, 0.08]] + lower[1:] + lower[-1:],
                      cap=0.03))
        S["neck"] = dict(ray=((0.95, 0, 0.2), 48.0), R=0.31, dir=48.0,
                         lengths=[0.2, 0.3, 0.4, 0.45, 0.56, 0.14, 0.12], poll=88.0,
                         knots=[0.0, 0.42, 0.82, 1.12, 1.35, 1.55, 1.78, 2.05, 2.17],
                         values=[[0.27] * 3, [0.22, 0.24, 0.2], [0.16, 0.18, 0.15], [0.125, 0.13, 0.12],
                                 [0.12, 0.14, 0.125], [0.115, 0.2, 0.13], [0.105, 0.16, 0.105],
                                 [0.09, 0.11, 0.085], [0.09, 0.1, 0.085]],
                         cap=0.075, cap_power=2.5)
        S["ears"] = dict(at=0.09, angle=55.0, R=0.06, target=(0.1, 0.25, 1.0),
                         lengths=[0.05, 0.08, 0.14], knots=[0, 0.06, 0.17, 0.27],
                         values=[0.05, 0.048, 0.04, 0.025], flat=(0.6, 1.0), cap=0.06,
                         cap_power=1.6)
        S["horns"] = None
        S["tail"] = dict(ray=((-1.0, 0, 0.12), 163.0), R=0.13, psi=(212.0, 252.0),
                         lengths=[0.08, 0.14, 0.1, 0.26, 0.9],
                         knots=[0, 0.25, 0.5, 0.9, 1.3, 1.53],
                         values=[0.085, 0.072, 0.08, 0.1, 0.11, 0.105], cap=0.12)
    else:
        a = 1.4
        S["torso"] = dict(a=a, e_len=3.0, knots=[-a, -0.9, -0.1, 0.6, 0.95, a],
                          values=[[0.55, 0.55, 0.52], [0.58, 0.62, 0.6], [0.56, 0.7, 0.6],
                                  [0.56, 0.64, 0.54], [0.6, 0.56, 0.5], [0.56, 0.48, 0.44]],
                          expo=[2.7, 2.7, 2.8, 2.8, 2.7, 2.6])
        S["ground"] = -1.56
        lower = [[0.1, 0.1, 0.095], [0.078, 0.078, 0.074], [0.076, 0.076, 0.072],
                 [0.085, 0.085, 0.08], [0.072, 0.072, 0.07], [0.088, 0.088, 0.09]]
        S["legs"] = dict(
            front=dict(x=0.82, y=0.22, R=0.165, rest=(0.0, 0.0), Lf=0.17,
                       lengths=[0.22, 0.18, 0.18, 0.16, 0.08, 0.16],
                       knots=[0, 0.2, 0.4, 0.57, 0.7, 0.86, 0.97, 1.07, 1.15],
                       values=[[0.14, 0.14, 0.125], [0.14, 0.13, 0.115], [0.11, 0.11, 0.1]] + lower,
                       cap=0.03),
            hind=dict(x=-0.85, y=0.27, R=0.185, rest=(-18.0, 18.0), Lf=0.2,
                      lengths=[0.24, 0.2, 0.2, 0.16, 0.08, 0.16],
                      knots=[0, 0.22, 0.44, 0.62, 0.74, 0.9, 1.01, 1.11, 1.2],
                      values=[[0.16, 0.16, 0.135], [0.14, 0.15, 0.12], [0.1, 0.12, 0.095]] + lower,
                      cap=0.03))
        S["neck"] = dict(ray=((1.0, 0, 0.12), 5.0), R=0.42, dir=2.0,
                         lengths=[0.2, 0.3, 0.02, 0.4, 0.48, 0.12, 0.1], poll=42.0,
                         knots=[0.0, 0.35, 0.55, 0.78, 0.92, 1.1, 1.32, 1.5, 1.62],
                         values=[[0.34] * 3, [0.27, 0.3, 0.26], [0.21, 0.22, 0.2], [0.18, 0.19, 0.18],
                                 [0.18, 0.2, 0.19], [0.17, 0.22, 0.2], [0.15, 0.17, 0.17],
                                 [0.14, 0.15, 0.165], [0.14, 0.15, 0.165]],
                         cap=0.09, cap_power=2.8)
        S["ears"] = dict(at=0.06, angle=115.0, R=0.065, target=(-0.1, 1.0, -0.3),
                         lengths=[0.04, 0.06, 0.16], knots=[0, 0.05, 0.16, 0.26],
                         values=[0.05, 0.055, 0.065, 0.045], flat=(0.45, 1.0), cap=0.06,
                         cap_power=2.0)
        S["horns"] = dict(at=0.15, angle=50.0, R=0.065, target=(0.5, 0.4, 0.75),
                          lengths=[0.04, 0.16, 0.14], knots=[0, 0.08, 0.22, 0.34],
                          values=[0.052, 0.045, 0.03, 0.018], flat=(1.0, 1.0), cap=0.05,
                          cap_power=1.5)
        S["tail"] = dict(ray=((-1.0, 0, 0.2), 150.0), R=0.09, psi=(200.0, 266.0),
                         lengths=[0.07, 0.14, 0.08, 0.28, 1.1],
                         knots=[0, 0.2, 0.6, 1.3, 1.4, 1.6, 1.71],
                         values=[0.05, 0.04, 0.034, 0.03, 0.055, 0.065, 0.06], cap=0.09)
    return S


# --- the torso as an implicit surface (for attachment points and normals) -------------

def _torso_part(T):
    """The torso as a tube along x from -a to a: the knot semi-axes times the
    superellipse meridian factor (1 - |x/a|^e)^(1/e), an apex at each end."""
    a, e = T["a"], T["e_len"]
    phi = np.linspace(0.0, np.pi, 1601)
    c = np.cos(phi)
    x = -a * np.sign(c) * np.abs(c) ** (2.0 / e)
    return _Part("torso", lambda pose: [(2 * a, None, 0.0)], np.asarray(T["knots"]) + a, T["values"],
                 expo=T["expo"], scale=lambda s: _torso_scale(s - a, a, e),
                 samples=lambda: x + a, zone=0.45 * a, kmin=3,
                 hcap=lambda s: np.full(len(s), TORSO_EDGE))


def _torso_scale(x, a, e):
    return np.clip(1.0 - np.abs(np.asarray(x) / a) ** e, 0.0, 1.0) ** (1.0 / e)


class _Torso:
    """The torso's surface: at x the cross-section is the superellipse of the
    knot semi-axes times the meridian factor (1 - |x/a|^e)^(1/e)."""

    def __init__(self, T):
        self.T = T
        self.a = T["a"]
        self._axes, self._expo = _Pchip(T["knots"], T["values"]), _Pchip(T["knots"], T["expo"])

    def axes(self, x):
        x = np.atleast_1d(np.asarray(x, float))
        ax, ex = self._axes(x), self._expo(x)[:, 0]
        return ax * _torso_scale(x, self.a, self.T["e_len"])[:, None], ex

    def implicit(self, P):
        """< 0 inside, 0 on the surface (a superellipse norm minus 1)."""
        P = np.atleast_2d(P)
        ax, ex = self.axes(P[:, 0])
        N, B = P[:, 2], -P[:, 1]
        aN = np.where(N > 0, ax[:, 0], ax[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            g = (np.abs(N) / aN) ** ex + (np.abs(B) / ax[:, 2]) ** ex
        g = np.where(np.abs(P[:, 0]) >= self.a, np.inf, g)
        return g ** (1.0 / ex) - 1.0


def _ray_hit(implicit, origin, direction, far=3.0):
    """First crossing from inside (origin) to outside along direction (bisection)."""
    lo, hi = 0.0, far
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if implicit(origin + mid * direction)[0] < 0:
            lo = mid
        else:
            hi = mid
    return origin + 0.5 * (lo + hi) * direction


def _implicit_normal(implicit, p, eps=1e-5):
    g = np.array([(implicit(p + eps * e)[0] - implicit(p - eps * e)[0]) for e in np.eye(3)])
    return _unit(g)


def _down_hit(torso, x, y):
    """Point of the torso's underside above (x, y)."""
    return _ray_hit(torso.implicit, np.array([x, y, 0.0]), np.array([0.0, 0.0, -1.0]))


# --- the builder ------------------------------------------------------------------------

class _Model:
    """A built animal in the rest pose: per vertex the chain it hangs from,
    the arc length on that chain and its offset in the chain's frame there,
    so any pose re-evaluates the same vertices."""


class _Builder:
    def __init__(self, kind, h, seed):
        self.kind, self.h = kind, h
        self.rng = np.random.default_rng(seed)
        self.S = _spec(kind)
        self.V = []           # blocks of rest positions
        self.nv = 0
        self.chain = []       # per block: chain id
        self.sigma = []
        self.local = []
        self.F = []           # blocks of faces
        self.fpart = []
        self.part_of_vertex = []
        self.dead = np.zeros(0, bool)
        self.chains = []      # (name, elements-function, origin, frame)
        self.landmarks = {}

    # -- storage ---------------------------------------------------------
    def add_vertices(self, P, chain_id, sigma, local, part_id):
        P = np.asarray(P, float).reshape(-1, 3)
        ids = np.arange(self.nv, self.nv + len(P))
        self.V.append(P)
        self.chain.append(np.full(len(P), chain_id))
        self.sigma.append(np.broadcast_to(np.asarray(sigma, float), (len(P),)).copy())
        self.local.append(np.asarray(local, float).reshape(-1, 3))
        self.part_of_vertex.append(np.full(len(P), part_id))
        self.nv += len(P)
        return ids

    def add_faces(self, F, part_id):
        F = np.asarray(F, np.int64).reshape(-1, 3)
        self.F.append(F)
        self.fpart.append(np.full(len(F), part_id))
        self.dead = np.concatenate([self.dead, np.zeros(len(F), bool)])

    def arrays(self):
        return (np.concatenate(self.V), np.concatenate(self.F), np.concatenate(self.fpart))

    def new_chain(self, name, elements, origin, frame):
        self.chains.append((name, elements, np.asarray(origin, float), np.asarray(frame, float)))
        return len(self.chains) - 1

    def chain_of(self, cid, pose):
        name, elements, origin, frame = self.chains[cid]
        return _Chain(origin, frame, elements(pose))

    # -- rings ------------------------------------------------------------
    def _smooth_noise(self, n, amplitude):
        """Seeded smooth noise over ring index (a few random sinusoids)."""
        j = np.arange(n)
        out = np.zeros(n)
        for _ in range(3):
            out += np.sin(2 * np.pi * j / self.rng.uniform(5, 17) + self.rng.uniform(0, 2 * np.pi))
        return amplitude * out / 3.0

    def _plan(self, m, P, htarget):
        """Ring positions along the meridian arc length m (samples, increasing,
        with perimeters P and local edge targets htarget): spacing 0.866 h."""
        density = 1.0 / (_SQ3 * htarget)
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]) * np.diff(m))])
        n = max(2, int(round(cum[-1])))
        targets = (np.arange(1, n) + self._smooth_noise(n - 1, 0.18)) * cum[-1] / n
        return np.interp(targets, cum, m)

    def _ring_counts(self, P, htarget, kmin):
        xi = self._smooth_noise(len(P), 0.45)
        return np.maximum(kmin, np.round(P / htarget + xi)).astype(int)

    def _phases(self, k):
        off = np.empty(len(k))
        o = self.rng.uniform(0, 1)
        for j in range(len(k)):
            o = o + (0.5 + self.rng.uniform(-0.15, 0.15)) / k[j]
            off[j] = o
        return off

    # -- a tube -------------------------------------------------------------
    def tube(self, part, part_id, chain_id, s0, start_ring=None, loft=None):
        """Meshes `part` from centre-line position s0 to its apex. start_ring =
        (vertex ids, params) of a rim to start from, with `loft` the fillet
        between them; without, the tube starts at an apex of its own (torso)."""
        chain = self.chain_of(chain_id, None)
        L = chain.length
        s = part.meridian_samples(s0, L)
        ax, ex = part.axes(s, L)
        P, _ = _perimeters(ax, ex)
        # Edge target: h, or perimeter / kmin where the tube is thin; near an
        # apex it stays that of the zone's base (rings then thin out).
        z0, z1 = part.zones(s, L)
        Pbase = P.copy()
        if z0.any():
            Pbase[z0] = P[np.flatnonzero(z0)[-1] + 1]
        Pbase[z1] = P[np.flatnonzero(z1)[0] - 1]
        ht = np.minimum(self.h, Pbase / part.kmin)
        if part.hcap is not None:
            ht = np.minimum(ht, part.hcap(s))
        m = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(s), np.diff(P / (2 * np.pi))))])
        if loft is not None:
            M0 = loft["m"][-1]
            m_all = np.concatenate([loft["m"], M0 + m[1:]])
            P_all = np.concatenate([loft["P"], P[1:]])
            ht_all = np.concatenate([np.minimum(self.h, loft["ht"]), ht[1:]])
        else:
            M0, m_all, P_all, ht_all = 0.0, m, P, ht
        ring_m = self._plan(m_all, P_all, ht_all)
        is_loft = ring_m <= M0 if loft is not None else np.zeros(len(ring_m), bool)
        ring_s = np.interp(ring_m - M0, m, s)
        in_zone = np.interp(ring_m - M0, m, (z0 | z1).astype(float)) > 0.5
        k = self._ring_counts(np.interp(ring_m, m_all, P_all), np.interp(ring_m, m_all, ht_all),
                              np.where(in_zone & ~is_loft, 3, part.kmin))
        offs = self._phases(k)
        if start_ring is None:
            C, _ = chain.eval([s[0]])
            apex0 = self.add_vertices(C, chain_id, s[0], [[0.0, 0.0, 0.0]], part_id)[0]
        tube_s = ring_s[~is_loft]
        Cs, Rs = chain.eval(tube_s)
        axs, exs = part.axes(tube_s, L)
        ti = 0
        faces = []
        prev = start_ring
        for j in range(len(ring_m)):
            u = np.mod(offs[j] + np.arange(k[j]) / k[j], 1.0)
            if is_loft[j]:
                Pj, local = loft["eval"](np.interp(ring_m[j], loft["m"], loft["tau"]), u)
                ids = self.add_vertices(Pj, chain_id, 0.0, local, part_id)
            else:
                xy = _section_at(axs[ti], exs[ti], u)
                local = np.column_stack([xy, np.zeros(len(u))])
                Pj = Cs[ti] + local @ Rs[ti].T
                ids = self.add_vertices(Pj, chain_id, tube_s[ti], local, part_id)
                ti += 1
            if prev is None:
                faces.append(np.stack([np.full(k[j], apex0), ids, np.roll(ids, -1)], 1))
            else:
                faces.append(_zip(prev[0], prev[1], ids, u))
            prev = (ids, u)
        C, _ = chain.eval([s[-1]])
        apex = self.add_vertices(C, chain_id, s[-1], [[0.0, 0.0, 0.0]], part_id)[0]
        faces.append(np.stack([np.roll(prev[0], -1), prev[0], np.full(len(prev[0]), apex)], 1))
        self.add_faces(np.concatenate(faces), part_id)
        return apex

    # -- cutting a disc and attaching a limb ----------------------------------
    def attach(self, parent_id, p0, d0, R, frame0, rmin, implicit=None):
        """Removes the parent's faces inside the cylinder of radius R about
        the line p0 + t d0 (near p0), moves the rim onto the cylinder and
        returns (rim ids, rim params, loft data) for the child's fillet."""
        V, F, fpart = self.arrays()
        live = np.flatnonzero(~self.dead & (fpart == parent_id))
        Fp = F[live]
        rel = V - p0
        near = np.linalg.norm(rel, axis=1) < 3 * R + 4 * self.h
        local_faces = near[Fp].any(axis=1)
        Fl, live_l = Fp[local_faces], live[local_faces]
        el = np.linalg.norm(V[Fl[:, [1, 2, 0]]] - V[Fl], axis=2)
        hloc = float(np.median(el))
        Reff = max(R, 0.6 * hloc)
        # Vertices shared with other parts (rims of earlier limbs) stay.
        protected = np.zeros(len(V), bool)
        protected[F[~self.dead & (fpart != parent_id)].ravel()] = True
        blocked = protected[Fl].any(axis=1)
        # faces whose centroid lies in the cylinder (near p0, not across the parent)
        crel = V[Fl].mean(axis=1) - p0
        ct = crel @ d0
        crho = np.linalg.norm(crel - ct[:, None] * d0, axis=1)
        fnl = np.cross(V[Fl[:, 1]] - V[Fl[:, 0]], V[Fl[:, 2]] - V[Fl[:, 0]])
        facing = fnl @ d0 > 0.0
        N0, B0 = frame0[:, 0], frame0[:, 1]
        X, Y = rel @ N0, rel @ B0                      # projection on the plane normal to d0
        # the face the axis crosses (nearest p0 along the axis)
        xa, ya = X[Fl], Y[Fl]
        # (signs of the origin against each projected edge: all equal inside)
        cr = np.stack([xa[:, c] * ya[:, (c + 1) % 3] - ya[:, c] * xa[:, (c + 1) % 3]
                       for c in range(3)], 1)
        hit = facing & ~blocked & ((cr >= 0).all(axis=1) | (cr <= 0).all(axis=1))
        if not hit.any():
            raise RuntimeError("limb axis misses its parent")
        seed_face = np.flatnonzero(hit)[np.argmin(np.abs(ct[hit]))]
        removed = (crho < Reff) & (np.abs(ct) < 1.5 * (Reff + hloc)) & facing & ~blocked
        removed[seed_face] = True
        removed = _component(Fl, removed, seed_face)
        for _attempt in range(12):
            for _ in range(50):
                closure = np.zeros(len(V), bool)
                closure[Fl[removed].ravel()] = True
                add = ~removed & closure[Fl].all(axis=1) & ~blocked
                if not add.any():
                    break
                removed |= add
            try:
                rim = _hole_loop(Fl[~removed], Fl[removed])
                nv = len(np.unique(Fl[removed]))
                ne = len(np.unique(np.sort(np.concatenate(
                    [Fl[removed][:, [0, 1]], Fl[removed][:, [1, 2]], Fl[removed][:, [2, 0]]]), 1), axis=0))
                if nv - ne + removed.sum() != 1:
                    raise ValueError("cut region is not a disc")
            except (ValueError, KeyError):
                closure = np.zeros(len(V), bool)
                closure[Fl[removed].ravel()] = True
                removed |= closure[Fl].any(axis=1) & ~blocked
                continue
            # the rim must wind once around the axis, not too close to it
            x, y = X[rim], Y[rim]
            u_raw = np.mod(-np.arctan2(y, x) / (2 * np.pi), 1.0)
            turn = np.sum(np.mod(np.diff(np.append(u_raw, u_raw[0])) + 0.5, 1.0) - 0.5)
            x2, y2 = np.roll(x, -1), np.roll(y, -1)
            seg = np.hypot(x2 - x, y2 - y)
            w = np.clip(-(x * (x2 - x) + y * (y2 - y)) / np.maximum(seg, 1e-300) ** 2, 0, 1)
            gap = np.hypot(x + w * (x2 - x), y + w * (y2 - y)).min()
            if turn > 0.5 and gap > 0.35 * min(Reff, np.hypot(x, y).mean()):
                break
            v = rim[np.argmin(np.hypot(x, y))]
            grow = (Fl == v).any(axis=1) & ~blocked & ~removed
            if not grow.any():      # hemmed in by a neighbouring limb: accept a lopsided disc
                if turn > 0.5 and gap > 0.12 * min(Reff, np.hypot(x, y).mean()):
                    break
                raise RuntimeError("could not cut a disc for a limb: too close to another limb")
            removed |= grow
        else:  # pragma: no cover
            raise RuntimeError("could not cut a disc for a limb")
        # vertex normals at the rim (all parent faces around, before the cut)
        touch = np.isin(Fl, rim).any(axis=1)
        Ft = Fl[touch]
        fn = np.cross(V[Ft[:, 1]] - V[Ft[:, 0]], V[Ft[:, 2]] - V[Ft[:, 0]])
        vn = np.zeros((len(V), 3))
        for c in range(3):
            np.add.at(vn, Ft[:, c], fn)
        n = _unit(vn[rim])
        self.dead[live_l[removed]] = True
        # rim parameters: arc length (monotone) aligned with the azimuth
        seg = np.hypot(np.diff(np.append(x, x[0])), np.diff(np.append(y, y[0])))
        sfrac = np.concatenate([[0.0], np.cumsum(seg)[:-1]]) / seg.sum()
        off = np.angle(np.mean(np.exp(2j * np.pi * (u_raw - sfrac)))) / (2 * np.pi)
        u = np.mod(sfrac + off, 1.0)
        th = -2 * np.pi * u
        e = np.cos(th)[:, None] * N0 + np.sin(th)[:, None] * B0
        dn = n @ d0
        if dn.min() < 0.1:
            raise RuntimeError(f"limb axis too oblique to the parent surface {dn} {Reff} {len(rim)}")
        # onto the cylinder (next to a neighbouring limb's rim: only inwards)
        beside = np.zeros(len(V), bool)
        beside[Fl[protected[Fl].any(axis=1)].ravel()] = True
        rr = np.where(beside[rim], np.minimum(Reff, np.hypot(x, y)), Reff)
        rr = np.maximum(rr, np.minimum(Reff, 1.1 * rmin(u)))     # room for the fillet
        tt = np.einsum("ij,ij->i", V[rim] - p0 - rr[:, None] * e, n) / dn
        Q = p0 + rr[:, None] * e + tt[:, None] * d0
        self.move_vertices(rim, Q)
        if implicit is not None:
            self.relax(implicit, Fl[~removed], rim, protected)
        # slope of the parent surface at the rim, in the meridian plane (rho, t)
        slope = np.stack([-dn, np.einsum("ij,ij->i", n, e)], 1)
        slope /= np.linalg.norm(slope, axis=1, keepdims=True)
        return rim, u, dict(Reff=Reff, u=u, t=tt, r=rr, slope=slope)

    def move_vertices(self, ids, Q):
        """Moves vertices (rest positions and their chain offsets)."""
        ids = np.asarray(ids)
        starts = np.cumsum([0] + [len(b) for b in self.V])
        blocks = np.searchsorted(starts, ids, side="right") - 1
        for b in np.unique(blocks):
            m = blocks == b
            rows = ids[m] - starts[b]
            self.V[b][rows] = Q[m]
            for cid in np.unique(self.chain[b][rows]):
                k = self.chain[b][rows] == cid
                C, Rm = self.chain_of(cid, None).eval(self.sigma[b][rows[k]])
                self.local[b][rows[k]] = np.einsum("nji,nj->ni", Rm, Q[m][k] - C)

    def relax(self, implicit, F, rim, protected, rings=2, iterations=5):
        """Evens out the parent's triangles next to a moved rim: a few tangential
        Laplacian steps of the vertices within `rings` of it (not the rim, not
        other parts' vertices), each projected back onto the parent's exact
        surface (implicit), so the shape does not change."""
        V = np.concatenate(self.V)
        near = np.zeros(len(V), bool)
        near[rim] = True
        for _ in range(rings):
            near[F[near[F].any(axis=1)].ravel()] = True
        free = near.copy()
        free[rim] = False
        free &= ~protected
        ids = np.flatnonzero(free)
        if not len(ids):
            return
        E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
        E = E[free[E[:, 0]]]
        P = V.copy()
        eps = 1e-6
        for _ in range(iterations):
            acc = np.zeros((len(V), 3))
            cnt = np.zeros(len(V))
            np.add.at(acc, E[:, 0], P[E[:, 1]])
            np.add.at(cnt, E[:, 0], 1.0)
            X = P[ids]
            with np.errstate(all="ignore"):
                grad = np.stack([(implicit(X + eps * e) - implicit(X - eps * e)) / (2 * eps)
                                 for e in np.eye(3)], 1)
                n = grad / np.linalg.norm(grad, axis=1, keepdims=True)
            n = np.nan_to_num(n)
            d = acc[ids] / cnt[ids, None] - X
            d -= np.einsum("ij,ij->i", d, n)[:, None] * n
            X = X + 0.5 * d
            with np.errstate(all="ignore"):
                for _ in range(3):          # Newton steps onto the surface
                    g = implicit(X)
                    grad = np.stack([(implicit(X + eps * e) - implicit(X - eps * e)) / (2 * eps)
                                     for e in np.eye(3)], 1)
                    X = X - (g / np.einsum("ij,ij->i", grad, grad))[:, None] * grad
                ok = np.isfinite(X).all(axis=1) & (np.abs(implicit(X)) < 1e-9)
            P[ids[ok]] = X[ok]          # (near the torso's apexes: left alone)
        self.move_vertices(ids, P[ids])

    def limb(self, part, name, parent_id, p0, d0, R, Lf, frame0, elements, part_id,
             implicit=None):
        """Cuts the parent, lofts the fillet up to Lf along d0, then the tube."""
        cid = self.new_chain(name, elements, p0, frame0)
        chain = self.chain_of(cid, None)
        L = chain.length
        ax1, ex1 = part.axes(np.array([Lf, Lf + 1e-3]), L)

        def section_radius(u, i):
            """Radius of the tube's section at Lf (i = 0) or just beyond (i = 1)
            in the direction of azimuth parameter u."""
            th = -2 * np.pi * u
            c, s = np.cos(th), np.sin(th)
            aN = np.where(c > 0, ax1[i, 0], ax1[i, 1])
            e = ex1[i]
            return (np.abs(c / aN) ** e + np.abs(s / ax1[i, 2]) ** e) ** (-1.0 / e)

        try:
            rim, u_rim, rimdata = self.attach(parent_id, p0, d0, R, frame0,
                                              lambda u: section_radius(u, 0), implicit)
        except RuntimeError as error:
            raise RuntimeError(f"{self.kind} {name}, h={self.h:.4g}: {error}") from None
        Reff, tr, sl, rr = rimdata["Reff"], rimdata["t"], rimdata["slope"], rimdata["r"]
        r1max = ax1[0].max()
        if tr.max() > Lf - 0.1 * (Reff - r1max):
            raise RuntimeError(f"{name}: fillet too short for the parent's curvature")
        if (rr < 1.02 * section_radius(u_rim, 0)).any():
            raise RuntimeError(f"{name}: no room for the fillet")
        order = np.argsort(u_rim)
        us, ts, sls, rs = u_rim[order], tr[order], sl[order], rr[order]

        def rim_at(u):
            t0 = np.interp(u, us, ts, period=1.0)
            r0 = np.interp(u, us, rs, period=1.0)
            m0 = np.stack([np.interp(u, us, sls[:, 0], period=1.0),
                           np.interp(u, us, sls[:, 1], period=1.0)], -1)
            return t0, r0, m0 / np.linalg.norm(m0, axis=-1, keepdims=True)

        def hermite(tau, u):
            """(rho, t) on the fillet at tau in [0, 1] (arrays broadcast)."""
            t0, r0, m0 = rim_at(u)
            r1 = section_radius(u, 0)
            dr1 = (section_radius(u, 1) - r1) / 1e-3
            lam0 = 1.3 * (r0 - r1)
            lam1 = 1.3 * (Lf - t0)
            h00 = 2 * tau ** 3 - 3 * tau ** 2 + 1
            h10 = tau ** 3 - 2 * tau ** 2 + tau
            h01 = -2 * tau ** 3 + 3 * tau ** 2
            h11 = tau ** 3 - tau ** 2
            rho = h00 * r0 + h10 * lam0 * m0[..., 0] + h01 * r1 + h11 * lam1 * dr1
            t = h00 * t0 + h10 * lam0 * m0[..., 1] + h01 * Lf + h11 * lam1
            return rho, t

        tau = np.linspace(0.0, 1.0, 81)
        ua = (np.arange(48) + 0.5) / 48
        rho, t = hermite(tau[:, None], ua[None, :])
        if np.diff(rho, axis=0).max() > 0.05 * Reff or np.diff(t, axis=0).min() < -0.25 * (Reff - r1max):
            raise RuntimeError(f"{name}: fillet profile folds ({np.diff(rho, axis=0).max()}, "
                               f"{np.diff(t, axis=0).min()}, {Reff}, {rs}, {ts}, {Lf})")
        ml = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(rho, axis=0), np.diff(t, axis=0)).mean(1))])
        lP = 2 * np.pi * rho.mean(1)

        def loft_eval(tau_j, u):
            rho_j, t_j = hermite(np.full(len(u), tau_j), u)
            th = -2 * np.pi * u
            local = np.column_stack([rho_j * np.cos(th), rho_j * np.sin(th), t_j])
            return p0 + local @ frame0.T, local

        loft = dict(m=ml, P=lP, ht=lP / part.kmin, tau=tau, eval=loft_eval)
        return cid, self.tube(part, part_id, cid, Lf, start_ring=(rim, u_rim), loft=loft)


def _leg_elements(leg, key, front):
    hip0, knee0 = leg["rest"]
    sign = 1.0 if front else -1.0
    l_hip, L_up, l_knee, L_low, l_fet, L_last = leg["lengths"]

    def elements(pose):
        hip, knee = (pose or REST).get(key, (0.0, 0.0))
        fet = -(-(hip0) + sign * knee0)
        return [(leg["Lf"], None, 0.0), (l_hip, _Y, _deg(-(hip0 + hip))), (L_up, None, 0.0),
                (l_knee, _Y, _deg(sign * (knee0 + knee))), (L_low, None, 0.0),
                (l_fet, _Y, _deg(fet)), (leg["L_last"], None, 0.0)]
    return elements


def _build(kind, h, seed):
    b = _Builder(kind, h, seed)
    S = b.S
    torso_shape = _Torso(S["torso"])
    a = S["torso"]["a"]
    # torso: a tube along x with an apex at each end
    ids = {name: i for i, name in enumerate(PARTS)}
    tpart = _torso_part(S["torso"])
    tid = b.new_chain("torso", tpart.elements, [-a, 0.0, 0.0], _sagittal_frame([1.0, 0, 0]))
    b.tube(tpart, ids["torso"], tid, 0.0)
    # legs
    for key in LEGS:
        front = key[4] == "f"
        leg = dict(S["legs"]["front" if front else "hind"])
        side = 1.0 if key[5] == "l" else -1.0
        p0 = _down_hit(torso_shape, leg["x"], side * leg["y"])
        d0 = np.array([0.0, 0.0, -1.0])
        # the last straight piece ends on the ground in the rest pose
        leg["L_last"] = leg["lengths"][-1]
        probe = _Chain(p0, _sagittal_frame(d0), _leg_elements(leg, key, front)(None))
        leg["L_last"] += probe.eval([probe.length])[0][0, 2] - S["ground"]
        elements = _leg_elements(leg, key, front)
        L = sum(e[0] for e in elements(None))
        knots = np.asarray(leg["knots"], float) * (L / leg["knots"][-1])
        part = _Part(key, elements, knots, leg["values"], cap_len=leg["cap"], cap_power=3.0,
                     landmark="hoof_" + key[4:])
        cid, apex = b.limb(part, key, ids["torso"], p0, d0, leg["R"], leg["Lf"],
                           _sagittal_frame(d0), elements, ids[key], torso_shape.implicit)
        b.landmarks["hoof_" + key[4:]] = apex
    # neck and head
    nk = S["neck"]
    origin, ang = nk["ray"]
    ray = np.array([np.cos(_deg(ang)), 0.0, np.sin(_deg(ang))])
    p0 = _ray_hit(torso_shape.implicit, np.asarray(origin, float), ray)
    d0 = _implicit_normal(torso_shape.implicit, p0) * [1.0, 0.0, 1.0]
    d0 = _unit(d0)
    psi_neck = np.degrees(np.arctan2(d0[2], d0[0]))      # the root leaves along the normal
    Ls = nk["lengths"]
    poll = nk["poll"]
    muzzle = poll - nk["dir"]        # the nose ends horizontal in the rest pose

    def neck_elements(pose):
        # Rot_y(+x) turns a tangent downwards: the first arc turns the root to
        # nk["dir"] (+ the neck pose) above the horizontal.
        pose = pose or REST
        return [(Ls[0], None, 0.0), (Ls[1], _Y, _deg(psi_neck - nk["dir"] - pose.get("neck", 0.0))),
                (Ls[2], None, 0.0),
                (Ls[3], _Y, _deg(poll - pose.get("head", 0.0))), (Ls[4], None, 0.0),
                (Ls[5], _Y, _deg(-muzzle)), (Ls[6], None, 0.0)]
    # (Rot_y(+x) turns a tangent downwards: poll > 0 bends the head down,
    # -muzzle turns the nose forward again.)
    # The head carries ears (and horns) about one edge wide at 3000 faces:
    # its edges are capped at HEAD_EDGE, growing back to h along the neck.
    head_s0 = sum(Ls[:4])
    neck_part = _Part("neck", neck_elements, nk["knots"], nk["values"], cap_len=nk["cap"],
                      cap_power=nk["cap_power"], landmark="muzzle",
                      hcap=lambda s: HEAD_EDGE + 0.5 * np.maximum(head_s0 - 0.15 - s, 0.0))
    neck_cid, apex = b.limb(neck_part, "neck", ids["torso"], p0, d0, nk["R"], Ls[0],
                            _sagittal_frame(d0), neck_elements, ids["neck"], torso_shape.implicit)
    b.landmarks["muzzle"] = apex
    # ears and horns on the head's straight piece (rigid with the head)
    neck_chain = b.chain_of(neck_cid, None)
    for feature in ("ears", "horns"):
        spec = S[feature]
        if spec is None:
            continue
        s_a = head_s0 + spec["at"]
        C, Rm = neck_chain.eval([s_a])
        C, Rm = C[0], Rm[0]
        N, B, T = Rm[:, 0], Rm[:, 1], Rm[:, 2]
        head_axes = lambda s: neck_part.axes(np.atleast_1d(s), neck_chain.length)  # noqa: E731

        def head_implicit(P, C=C, Rm=Rm):
            P = np.atleast_2d(P)
            loc = (P - C) @ Rm
            ax, ex = head_axes(s_a + loc[:, 2])
            aN = np.where(loc[:, 0] > 0, ax[:, 0], ax[:, 1])
            g = (np.abs(loc[:, 0]) / aN) ** ex + (np.abs(loc[:, 1]) / ax[:, 2]) ** ex
            return g ** (1.0 / ex) - 1.0

        for side, suffix in ((1.0, "_l"), (-1.0, "_r")):
            left = -side * B          # B = T x N points to the animal's right
            alpha = _deg(spec["angle"])
            p0 = _ray_hit(head_implicit, C, np.cos(alpha) * N + np.sin(alpha) * left, far=1.0)
            d0 = _implicit_normal(head_implicit, p0)
            # root along the head's normal, then an arc turning it to `target`
            target = _unit(np.asarray(spec["target"], float) * [1.0, side, 1.0])
            turn = float(np.arccos(np.clip(d0 @ target, -1, 1)))
            bend_axis = _unit(np.cross(d0, target))
            Le = spec["lengths"]
            elements = (lambda Le, bend_axis, turn: lambda pose: [
                (Le[0], None, 0.0), (Le[1], bend_axis, turn), (Le[2], None, 0.0)]
            )(Le, bend_axis, turn)
            name = feature[:-1] + suffix
            L = sum(Le)
            vals = np.asarray(spec["values"], float)
            fl_n, fl_b = spec["flat"]
            # round at the root, flattened beyond it (N0 faces the head's front)
            values = np.stack([vals, vals, vals], 1)
            values[1:, 0] *= fl_n
            values[1:, 1] *= fl_n
            values[1:, 2] *= fl_b
            part = _Part(name, elements, np.asarray(spec["knots"]) * L / spec["knots"][-1], values,
                         cap_len=spec["cap"], cap_power=spec["cap_power"], kmin=5)
            N0 = _unit(T - (T @ d0) * d0)
            frame0 = np.stack([N0, np.cross(d0, N0), d0], 1)
            cid, _ = b.limb(part, name, ids["neck"], p0, d0, spec["R"], Le[0], frame0, elements,
                            ids[name])
            # ears and horns are rigid with the head: re-anchor them on the neck chain at s_a
            b.rigid_children = getattr(b, "rigid_children", []) + [(cid, neck_cid, s_a)]
    # tail
    tl = S["tail"]
    origin, ang = tl["ray"]
    ray = np.array([np.cos(_deg(ang)), 0.0, np.sin(_deg(ang))])
    p0 = _ray_hit(torso_shape.implicit, np.asarray(origin, float), ray)
    d0 = _unit(_implicit_normal(torso_shape.implicit, p0) * [1.0, 0.0, 1.0])
    psi_tail = np.degrees(np.arctan2(d0[2], d0[0]))
    Lt = tl["lengths"]
    psi1, psi2 = tl["psi"]

    def tail_elements(pose):
        # root along the normal; arc to psi1 (the dock), arc to psi2 (hanging);
        # Rot_y(-x) turns the tangent up: from back (180) on towards down (270).
        pose = pose or REST
        return [(Lt[0], None, 0.0), (Lt[1], _Y, _deg(psi_tail - psi1)), (Lt[2], None, 0.0),
                (Lt[3], _Y, _deg(psi1 - psi2 + pose.get("tail", 0.0))), (Lt[4], None, 0.0)]
    L = sum(Lt)
    tail_part = _Part("tail", tail_elements, np.asarray(tl["knots"]) * L / tl["knots"][-1],
                      tl["values"], cap_len=tl["cap"], cap_power=2.0, landmark="tail")
    _, apex = b.limb(tail_part, "tail", ids["torso"], p0, d0, tl["R"], Lt[0], _sagittal_frame(d0),
                     tail_elements, ids["tail"], torso_shape.implicit)
    b.landmarks["tail"] = apex
    return _finish(b)


def _finish(b):
    """Drops the cut-out vertices, re-anchors rigid children, returns a _Model."""
    V, F, fpart = b.arrays()
    F, fpart = F[~b.dead], fpart[~b.dead]
    chain = np.concatenate(b.chain)
    sigma = np.concatenate(b.sigma)
    local = np.concatenate(b.local)
    vpart = np.concatenate(b.part_of_vertex)
    rigid = np.zeros(len(V), bool)
    for cid, parent_cid, s_a in getattr(b, "rigid_children", []):
        m = chain == cid
        rigid |= m
        C, R = b.chain_of(parent_cid, None).eval([s_a])
        chain[m] = parent_cid
        sigma[m] = s_a
        local[m] = (V[m] - C[0]) @ R[0]
    used = np.unique(F)
    remap = -np.ones(len(V), np.int64)
    remap[used] = np.arange(len(used))
    model = _Model()
    model.kind = b.kind
    model.V = V[used]
    model.F = remap[F].astype(np.int32)
    model.fpart = fpart
    model.chain_id, model.sigma, model.local = chain[used], sigma[used], local[used]
    model.vpart = vpart[used]
    model.rigid = rigid[used]
    model.landmarks = {k: int(remap[v]) for k, v in b.landmarks.items()}
    model.chains = b.chains
    model.h = b.h
    return model


def _positions(model, pose):
    V = np.empty((len(model.sigma), 3))
    for cid, (name, elements, origin, frame) in enumerate(model.chains):
        m = model.chain_id == cid
        if not m.any():
            continue
        C, R = _Chain(origin, frame, elements(pose)).eval(model.sigma[m])
        V[m] = C + np.einsum("nij,nj->ni", R, model.local[m])
    return V


# --- jitter -----------------------------------------------------------------------------

def _face_normals(V, F):
    return np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])


def _jitter(model, amount, seed):
    """Moves every vertex tangentially by up to amount x its local edge length
    (uniform in a disc) and normally by ~1% of that; moves that would fold
    or crush a face are halved until none does."""
    V, F = model.V, model.F
    rng = np.random.default_rng([seed, 7919])
    fn = _face_normals(V, F)
    area2 = np.linalg.norm(fn, axis=1)
    vn = np.zeros_like(V)
    for c in range(3):
        np.add.at(vn, F[:, c], fn)
    vn = _unit(vn)
    # local length: mean incident edge, but at most 1.15 x the smallest altitude
    e = np.linalg.norm(V[F[:, [1, 2, 0]]] - V[F], axis=2)
    alt = area2[:, None] / np.maximum(e, 1e-300)
    n = len(V)
    esum, ecnt = np.zeros(n), np.zeros(n)
    amin = np.full(n, np.inf)
    for c in range(3):
        np.add.at(esum, F[:, c], e[:, c] + e[:, (c + 2) % 3])
        np.add.at(ecnt, F[:, c], 2)
        np.minimum.at(amin, F[:, c], alt.min(axis=1))
    ell = np.minimum(esum / ecnt, 1.15 * amin)
    t1 = _unit(np.cross(vn, rng.normal(size=(n, 3))))
    t2 = np.cross(vn, t1)
    r = amount * ell * np.sqrt(rng.uniform(size=n))
    phi = rng.uniform(0, 2 * np.pi, size=n)
    d = (r * np.cos(phi))[:, None] * t1 + (r * np.sin(phi))[:, None] * t2
    d += (0.01 * amount * ell * np.clip(rng.normal(size=n), -2.5, 2.5))[:, None] * vn
    # Carried by the chains: along a tube the tangential part moves the arc
    # length (so bending a joint compresses the jitter with the triangles),
    # the rest the offset in the frame; ears and horns are rigid.
    dl = np.empty_like(d)
    for cid, (name, elements, origin, frame) in enumerate(model.chains):
        m = model.chain_id == cid
        if m.any():
            _, R = _Chain(origin, frame, elements(None)).eval(model.sigma[m])
            dl[m] = np.einsum("nji,nj->ni", R, d[m])
    along = np.where(model.rigid, 0.0, dl[:, 2])
    dl[:, 2] = np.where(model.rigid, dl[:, 2], 0.0)
    sigma0, local0 = model.sigma.copy(), model.local.copy()
    scale = np.ones(n)
    scale[list(model.landmarks.values())] = 0.0     # landmarks stay on their exact points
    for _ in range(40):
        model.sigma = sigma0 + scale * along
        model.local = local0 + scale[:, None] * dl
        W = _positions(model, None)
        wn = _face_normals(W, F)
        wa = np.linalg.norm(wn, axis=1)
        bad = (np.einsum("ij,ij->i", wn, fn) < 0.5 * wa * area2) | (wa < 0.25 * area2)
        if not bad.any():
            break
        scale[np.unique(F[bad])] *= 0.5
    else:
        scale[np.unique(F[bad])] = 0.0
        model.sigma = sigma0 + scale * along
        model.local = local0 + scale[:, None] * dl
        W = _positions(model, None)
    model.V = W


# --- public API -------------------------------------------------------------------------

# First resolution guess: faces ~ area / (0.433 h^2) + the thin parts' share
# (tail, lower legs, ears at their smallest ring counts; the finer head).
_AREA = {"horse": 14.0, "cow": 15.0}
_THIN = {"horse": 1300.0, "cow": 1600.0}


@functools.lru_cache(maxsize=16)
def _model(kind, faces, seed, jitter):
    """The rest-pose model for a face budget: the edge length h is guessed,
    then corrected (secant on log faces against log h) until the count is
    within 8%, or stops changing (at the smallest budgets the capped torso
    and head and the thinnest parts set a floor of ~2900-3300 faces)."""
    target = int(faces)
    if target < MIN_FACES:
        raise ValueError(f"faces must be at least {MIN_FACES}")
    h = (_AREA[kind] / (0.433 * max(target - _THIN[kind], 0.3 * target))) ** 0.5
    tried = []
    for _ in range(4):
        model = _build(kind, h, seed)
        m = len(model.F)
        tried.append((h, m))
        if abs(m / target - 1.0) < 0.08:
            break
        if len(tried) == 1:
            p = 2.0
        else:
            (h1, m1), (h2, m2) = tried[-2], tried[-1]
            if abs(m2 - m1) < 0.03 * m1:
                break                   # saturated: coarser h no longer removes faces
            p = np.clip(np.log(m2 / m1) / np.log(h1 / h2), 1.0, 2.5) if h1 != h2 else 2.0
        h = h * (m / target) ** (1.0 / p)
    if jitter:
        _jitter(model, float(jitter), seed)
    return model


def quadruped(kind="horse", faces=6000, pose=None, seed=0, jitter=0.0, return_parts=False):
    """A closed genus-0 horse-like or cow-like mesh with known landmarks.

    kind: "horse" or "cow". faces: approximate face count, 3000 to 100000
    and more (within ~10%; at least MIN_FACES, and near 3000 the count
    floors at ~2900-3300, the thin parts' and the head's share). pose: None
    (standing rest pose) or a dict of
    degrees, keys "leg_fl", "leg_fr", "leg_hl", "leg_hr" -> (hip, knee),
    "neck", "head", "tail" -> angle (missing keys: 0; see POSE_RANGES, WALK,
    GALLOP). seed: tessellation only. jitter: scan-like irregular
    triangles, 0 to 0.4.

    Returns V float64 (n, 3), F int32 (m, 3) (outward, counter-clockwise),
    landmarks {name: vertex index} for the names of LANDMARKS; with
    return_parts also {part name: vertex indices} (PARTS; a limb's rim
    vertices belong to its parent).
    """
    if kind not in ("horse", "cow"):
        raise ValueError(f"kind must be 'horse' or 'cow', not {kind!r}")
    if not 0.0 <= float(jitter) <= 0.4:
        raise ValueError("jitter must be in [0, 0.4]")
    if pose is not None:
        for key in pose:
            if key not in REST:
                raise ValueError(f"unknown pose key {key!r}")
    model = _model(kind, int(faces), int(seed), float(jitter))
    V = model.V.copy() if pose is None else _positions(model, pose)
    out = (V, model.F.copy(), dict(model.landmarks))
    if return_parts:
        out += ({name: np.flatnonzero(model.vpart == i) for i, name in enumerate(PARTS)
                 if (model.vpart == i).any()},)
    return out


def transform(V, F, scale=1.0, rotation=None, offset=(0.0, 0.0, 0.0), inside_out=False):
    """(V2, F2): V scaled, then rotated (3 x 3, applied as V @ rotation.T),
    then offset; inside_out reverses every face's winding."""
    V2 = np.asarray(V, np.float64) * float(scale)
    if rotation is not None:
        V2 = V2 @ np.asarray(rotation, np.float64).T
    V2 = V2 + np.asarray(offset, np.float64)
    F2 = np.asarray(F, np.int32)
    if inside_out:
        F2 = F2[:, ::-1]
    return V2, np.ascontiguousarray(F2, dtype=np.int32)


# --- checks shared by tests and benchmarks -------------------------------------------------

def landmark_vertices(landmarks):
    """The landmark vertex indices of quadruped() in the order of LANDMARKS."""
    return np.array([landmarks[name] for name in LANDMARKS])


def random_rotation(seed):
    """A proper rotation (det +1), drawn from `seed`."""
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def landmark_errors(morph, LA, VB, LB):
    """For a paramorph_native.Morph of A into B and landmark vertices LA, LB:
    per landmark the distance from where A's lands at t = 1 to B's, as a share
    of B's diagonal, and whether it lands nearest its own counterpart."""
    landed = np.asarray(morph.target)[np.asarray(morph.vertex_of_a)[LA]]
    distances = np.linalg.norm(landed[:, None, :] - VB[LB][None], axis=2)
    return np.diag(distances) / np.linalg.norm(np.ptp(VB, axis=0)), np.argmin(distances, axis=1) == np.arange(len(LB))


def folded_faces(morph):
    """Merged faces turned over on the morph's sphere."""
    S, F = np.asarray(morph.sphere), np.asarray(morph.faces)
    return int((np.einsum("ij,ij->i", S[F[:, 0]], np.cross(S[F[:, 1]], S[F[:, 2]])) <= 0).sum())


def _tri_tri(A, B, eps):
    """Vectorised test for pairs of triangles A, B (n, 3, 3) that cross
    (non-coplanar; touching within eps does not count)."""
    def side(P, T):
        n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        d = np.einsum("nkj,nj->nk", P - T[:, None, 0], n)
        return n, np.where(np.abs(d) < eps, 0.0, d)

    nB, dA = side(A, B)          # A's corners against B's plane
    nA, dB = side(B, A)
    sepA = (dA > 0).all(1) | (dA < 0).all(1)
    sepB = (dB > 0).all(1) | (dB < 0).all(1)
    cand = ~(sepA | sepB)
    cand &= ~((dA == 0).all(1) | (dB == 0).all(1))   # coplanar: ignored
    out = np.zeros(len(A), bool)
    if not cand.any():
        return out
    A, B, dA, dB, nA, nB = A[cand], B[cand], dA[cand], dB[cand], nA[cand], nB[cand]
    D = np.cross(nA, nB)

    def interval(T, d):
        p = np.einsum("nkj,nj->nk", T, D)
        lo = np.full(len(T), np.inf)
        hi = np.full(len(T), -np.inf)
        for i, j in ((0, 1), (1, 2), (2, 0)):
            cross = (d[:, i] * d[:, j] < 0)
            w = np.where(cross, d[:, i] / np.where(cross, d[:, i] - d[:, j], 1.0), 0.0)
            x = p[:, i] + w * (p[:, j] - p[:, i])
            lo = np.where(cross, np.minimum(lo, x), lo)
            hi = np.where(cross, np.maximum(hi, x), hi)
            on = d[:, i] == 0
            lo = np.where(on, np.minimum(lo, p[:, i]), lo)
            hi = np.where(on, np.maximum(hi, p[:, i]), hi)
        return lo, hi

    loA, hiA = interval(A, dA)
    loB, hiB = interval(B, dB)
    tol = eps * np.linalg.norm(D, axis=1)
    out[cand] = np.maximum(loA, loB) < np.minimum(hiA, hiB) - tol
    return out


def self_intersections(V, F, eps_rel=1e-9):
    """(k, 2) pairs of faces that share no vertex and cross each other."""
    V = np.asarray(V, np.float64)
    F = np.asarray(F, np.int64)
    T = V[F]
    lo, hi = T.min(1), T.max(1)
    cell = 1.5 * np.median(hi - lo)
    g0 = np.floor(lo / cell).astype(np.int64)
    g1 = np.floor(hi / cell).astype(np.int64)
    span = g1 - g0 + 1
    if span.max() > 4:      # huge faces: coarser grid
        cell *= span.max() / 4
        g0 = np.floor(lo / cell).astype(np.int64)
        g1 = np.floor(hi / cell).astype(np.int64)
        span = g1 - g0 + 1
    # (cell key, face) for every cell a face's box overlaps
    keys, faces = [], []
    for dx in range(span[:, 0].max()):
        for dy in range(span[:, 1].max()):
            for dz in range(span[:, 2].max()):
                m = (dx < span[:, 0]) & (dy < span[:, 1]) & (dz < span[:, 2])
                g = g0[m] + [dx, dy, dz]
                keys.append((g[:, 0] * 1_000_003 + g[:, 1]) * 1_000_033 + g[:, 2])
                faces.append(np.flatnonzero(m))
    keys, faces = np.concatenate(keys), np.concatenate(faces)
    order = np.argsort(keys, kind="stable")
    keys, faces = keys[order], faces[order]
    starts = np.flatnonzero(np.r_[True, keys[1:] != keys[:-1]])
    sizes = np.diff(np.r_[starts, len(keys)])
    pairs = []
    for size in np.unique(sizes):
        if size < 2:
            continue
        st = starts[sizes == size]
        i, j = np.triu_indices(size, 1)
        pairs.append(np.stack([faces[st[:, None] + i], faces[st[:, None] + j]], -1).reshape(-1, 2))
    if not pairs:
        return np.zeros((0, 2), np.int64)
    P = np.unique(np.sort(np.concatenate(pairs), axis=1), axis=0)
    share = (F[P[:, 0]][:, :, None] == F[P[:, 1]][:, None, :]).any(axis=(1, 2))
    P = P[~share]
    box = ((lo[P[:, 0]] <= hi[P[:, 1]]) & (lo[P[:, 1]] <= hi[P[:, 0]])).all(1)
    P = P[box]
    eps = eps_rel * np.linalg.norm(V.max(0) - V.min(0))
    hit = np.zeros(len(P), bool)
    for c in range(0, len(P), 200000):
        Q = P[c:c + 200000]
        hit[c:c + 200000] = _tri_tri(T[Q[:, 0]], T[Q[:, 1]], eps)
    return P[hit]


def part_distances(V, parts):
    """{(part a, part b): smallest vertex distance} for every pair of parts
    not attached to each other (ADJACENT), via boxes then brute force."""
    names = sorted(parts)
    out = {}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            if frozenset((a, b)) in ADJACENT:
                continue
            A, B = V[parts[a]], V[parts[b]]
            gap = np.maximum(A.min(0) - B.max(0), B.min(0) - A.max(0)).clip(0)
            d = float(np.linalg.norm(gap))
            if d > 0.2:
                out[(a, b)] = d
                continue
            lo = np.maximum(A.min(0), B.min(0)) - 0.2
            hi = np.minimum(A.max(0), B.max(0)) + 0.2
            A = A[((A >= lo) & (A <= hi)).all(1)]
            B = B[((B >= lo) & (B <= hi)).all(1)]
            best = np.inf
            for c in range(0, len(A), 2000):
                D = np.linalg.norm(A[c:c + 2000, None] - B[None], axis=2)
                if D.size:
                    best = min(best, float(D.min()))
            out[(a, b)] = min(best, 0.2) if np.isfinite(best) else 0.2
    return out


def mesh_stats(V, F):
    """Counts for checks: Euler characteristic, boundary/non-manifold edges,
    volume, smallest relative face area and angle (degrees)."""
    F = np.asarray(F, np.int64)
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    directed = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    _, dcounts = np.unique(directed, axis=0, return_counts=True)
    nv = len(np.unique(F))
    chi = nv - len(counts) + len(F)
    fn = _face_normals(V, F)
    area = 0.5 * np.linalg.norm(fn, axis=1)
    diag = np.linalg.norm(V.max(0) - V.min(0))
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]

    def ang(p, q, r):
        u, w = q - p, r - p
        cos = np.einsum("ij,ij->i", u, w) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1)
        return np.degrees(np.arccos(np.clip(cos, -1, 1)))

    angles = np.stack([ang(a, b, c), ang(b, c, a), ang(c, a, b)], 1)
    return dict(euler=chi, edges_not_two=int((counts != 2).sum()),
                repeated_directed=int((dcounts > 1).sum()), unused=len(V) - nv,
                volume=signed_volume(V, F), min_area=float(area.min() / diag ** 2),
                min_angle=float(angles.min()), max_angle=float(angles.max()))
