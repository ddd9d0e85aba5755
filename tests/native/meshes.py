"""Named test meshes built in numpy (DESIGN.md §5): every function returns
(V float64 (n,3), F int32 (m,3)); closed ones are oriented counter-clockwise
seen from outside. Deterministic (seeded)."""
import numpy as np


def icosphere(subdivisions=2):
    t = (1.0 + 5 ** 0.5) / 2.0
    V = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
                  [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]],
                 dtype=np.float64)
    F = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9],
                  [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2],
                  [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
                  [8, 6, 7], [9, 8, 1]], dtype=np.int64)
    V /= np.linalg.norm(V, axis=1, keepdims=True)
    for _ in range(subdivisions):
        V, F = _subdivide(V, F)
        V /= np.linalg.norm(V, axis=1, keepdims=True)
    return V, F.astype(np.int32)


def _subdivide(V, F):
    """Splits every triangle in four; midpoints shared through an edge key."""
    F = np.asarray(F, dtype=np.int64)
    edges = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    key = np.sort(edges, axis=1)
    unique, inverse = np.unique(key, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    mids = len(V) + inverse.reshape(3, -1).T  # (m, 3): midpoints of edges 01, 12, 20
    V = np.vstack([V, 0.5 * (V[unique[:, 0]] + V[unique[:, 1]])])
    a, b, c = F[:, 0], F[:, 1], F[:, 2]
    ab, bc, ca = mids[:, 0], mids[:, 1], mids[:, 2]
    F = np.concatenate([np.stack([a, ab, ca], 1), np.stack([b, bc, ab], 1),
                        np.stack([c, ca, bc], 1), np.stack([ab, bc, ca], 1)])
    return V, F


def _radial(V, radius):
    return V * radius[:, None]


def noisy_blob(subdivisions=3, seed=0):
    """Icosphere pushed by smooth random low-frequency radial noise (non-convex, star-shaped)."""
    V, F = icosphere(subdivisions)
    rng = np.random.default_rng(seed)
    r = np.ones(len(V))
    for _ in range(6):
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        r += 0.12 * np.cos(3.0 * (V @ direction) + rng.uniform(0, 2 * np.pi))
    return _radial(V, r) * np.array([1.0, 1.3, 0.8]), F


def tentacle_sphere(subdivisions=4, tentacles=6, length=4.0, seed=1):
    """A sphere with long thin fingers pulled out along `tentacles` directions."""
    V, F = icosphere(subdivisions)
    rng = np.random.default_rng(seed)
    dirs = rng.normal(size=(tentacles, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    r = np.ones(len(V))
    for d in dirs:
        cos = V @ d
        cap = np.clip((cos - 0.93) / 0.07, 0.0, 1.0)  # thin cap around the direction
        r += length * cap ** 0.5
    return _radial(V, r), F


def cad_box(n=8):
    """A box (2 x 1.4 x 1) with a raised square boss on its top: sharp 90° edges,
    grid-triangulated faces. Built by projecting a cube-sphere grid onto the box."""
    g = np.linspace(-1.0, 1.0, n + 1)
    u, v = np.meshgrid(g, g, indexing="ij")
    u, v = u.ravel(), v.ravel()
    quads = []
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    for i in range(n):
        for j in range(n):
            quads.append([idx[i, j], idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]])
    quads = np.array(quads)
    verts, faces = [], []
    one = np.ones_like(u)
    sides = [np.stack([one, u, v], 1), np.stack([-one, v, u], 1), np.stack([v, one, u], 1),
             np.stack([u, -one, v], 1), np.stack([u, v, one], 1), np.stack([v, u, -one], 1)]
    for P in sides:
        base = sum(len(x) for x in verts)
        verts.append(P)
        q = quads + base
        faces.append(np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]]))
    V = np.concatenate(verts)
    F = np.concatenate(faces)
    V, F = _weld(V, F)
    F = _orient_outward(V, F)
    # Boss: lift the middle of the top face, then box the shape.
    top = (V[:, 2] > 0.999) & (np.abs(V[:, 0]) < 0.45) & (np.abs(V[:, 1]) < 0.45)
    V = V * np.array([1.0, 0.7, 0.5])
    V[top, 2] += 0.3
    return V, F.astype(np.int32)


def bad_triangulation(seed=2):
    """Closed genus 0 with slivers, obtuse angles and mixed sizes: a convex hull of
    points clustered unevenly on an ellipsoid (dense patches, sparse regions)."""
    rng = np.random.default_rng(seed)
    dense = rng.normal(size=(400, 3)) * np.array([0.15, 0.15, 1.0]) + np.array([0, 0, 0])
    sparse = rng.normal(size=(60, 3))
    line = np.stack([np.linspace(-1, 1, 80), 0.02 * rng.normal(size=80), np.ones(80)], 1)
    P = np.concatenate([dense, sparse, line])
    P /= np.linalg.norm(P, axis=1, keepdims=True)
    V, F = _sphere_hull(P)
    return V * np.array([2.0, 1.0, 0.6]), F


def _sphere_hull(P):
    """Triangulation of points on the unit sphere = their convex hull (gift-free:
    Delaunay on the sphere via the lifting-free hull from numpy only)."""
    F = _convex_hull(P)
    return P, _orient_outward(P, F).astype(np.int32)


def _convex_hull(P):
    """Incremental 3D convex hull (O(n^2), fine for test sizes)."""
    n = len(P)
    i0, i1 = 0, 1
    i2 = next(i for i in range(2, n) if np.linalg.norm(np.cross(P[i1] - P[i0], P[i] - P[i0])) > 1e-9)
    i3 = next(i for i in range(3, n)
              if abs(np.dot(np.cross(P[i1] - P[i0], P[i2] - P[i0]), P[i] - P[i0])) > 1e-9)
    faces = [[i0, i1, i2], [i0, i2, i3], [i0, i3, i1], [i1, i3, i2]]
    centroid = P[[i0, i1, i2, i3]].mean(axis=0)
    faces = [f if np.dot(np.cross(P[f[1]] - P[f[0]], P[f[2]] - P[f[0]]), P[f[0]] - centroid) > 0
             else [f[0], f[2], f[1]] for f in faces]
    for p in range(n):
        if p in (i0, i1, i2, i3):
            continue
        visible = [f for f in faces
                   if np.dot(np.cross(P[f[1]] - P[f[0]], P[f[2]] - P[f[0]]), P[p] - P[f[0]]) > 1e-12]
        if not visible:
            continue
        edges = {}
        for f in visible:
            for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
                edges[(a, b)] = edges.get((a, b), 0) + 1
        horizon = [(a, b) for (a, b) in edges if (b, a) not in edges]
        faces = [f for f in faces if f not in visible] + [[a, b, p] for a, b in horizon]
    return np.array(faces, dtype=np.int64)


def _weld(V, F, tol=1e-9):
    keys = np.round(V / tol).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    return V[first], inverse.reshape(-1)[F]


def _orient_outward(V, F):
    """Flips faces whose normal points towards the centroid (convex-ish shapes only)."""
    c = V.mean(axis=0)
    a, b, d = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    n = np.cross(b - a, d - a)
    flip = np.einsum("ij,ij->i", n, (a + b + d) / 3 - c) < 0
    F = F.copy()
    F[flip] = F[flip][:, [0, 2, 1]]
    return F


def sized_sphere_mesh(target_faces):
    """Closed genus-0 blob with about `target_faces` faces: an icosphere of the
    nearest level, refined by a 1-to-3 split... keep to powers: 20 * 4^k, and for
    targets between levels, a subdivided icosphere with randomly split faces."""
    level = 0
    while 20 * 4 ** (level + 1) <= target_faces:
        level += 1
    V, F = noisy_blob(level, seed=7)
    # Split faces at their centroids (each adds 2 faces) until the target is reached.
    extra = max(0, (target_faces - len(F)) // 2)
    if extra:
        rng = np.random.default_rng(11)
        chosen = rng.choice(len(F), size=min(extra, len(F)), replace=False)
        centers = V[F[chosen]].mean(axis=1)
        new = np.arange(len(V), len(V) + len(chosen))
        a, b, c = F[chosen, 0], F[chosen, 1], F[chosen, 2]
        keep = np.ones(len(F), bool)
        keep[chosen] = False
        F = np.concatenate([F[keep], np.stack([a, b, new], 1), np.stack([b, c, new], 1),
                            np.stack([c, a, new], 1)]).astype(np.int32)
        V = np.vstack([V, centers])
    return V, F


def signed_volume(V, F):
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


# Broken meshes for the error paths.

def open_disc():
    V, F = icosphere(2)
    keep = V[F].mean(axis=1)[:, 2] < 0.3  # cut a cap off: one boundary loop
    F = F[keep]
    used = np.unique(F)
    remap = -np.ones(len(V), np.int64)
    remap[used] = np.arange(len(used))
    return V[used], remap[F].astype(np.int32)


def torus(n=16, m=8, R=1.0, r=0.35):
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    u, v = 2 * np.pi * i.ravel() / n, 2 * np.pi * j.ravel() / m
    V = np.stack([(R + r * np.cos(v)) * np.cos(u), (R + r * np.cos(v)) * np.sin(u), r * np.sin(v)], 1)
    idx = lambda a, b: (a % n) * m + (b % m)  # noqa: E731
    F = []
    for a in range(n):
        for b in range(m):
            F.append([idx(a, b), idx(a + 1, b), idx(a + 1, b + 1)])
            F.append([idx(a, b), idx(a + 1, b + 1), idx(a, b + 1)])
    return V, np.array(F, dtype=np.int32)


def two_spheres():
    V, F = icosphere(1)
    return np.vstack([V, V + [3.0, 0, 0]]), np.vstack([F, F + len(V)]).astype(np.int32)


def non_manifold_edge():
    """A sphere plus a fin: one extra triangle on an existing edge (3 faces there)."""
    V, F = icosphere(1)
    a, b = F[0, 0], F[0, 1]
    V = np.vstack([V, [[2.0, 2.0, 2.0]]])
    F = np.vstack([F, [[a, b, len(V) - 1]]]).astype(np.int32)
    return V, F


def nan_vertex():
    V, F = icosphere(1)
    V = V.copy()
    V[5, 1] = np.nan
    return V, F


def out_of_range_index():
    V, F = icosphere(1)
    F = F.copy()
    F[7, 2] = len(V) + 10
    return V, F


def zero_area_face():
    """Closed genus 0 where one face has zero area: a vertex moved onto the
    midpoint of the opposite edge of one of its faces."""
    V, F = icosphere(2)
    V = V.copy()
    a, b, c = F[10]
    V[c] = 0.5 * (V[a] + V[b])
    return V, F


FAMILIES_CLOSED = {
    "icosphere": lambda: icosphere(3),
    "noisy_blob": lambda: noisy_blob(3, seed=0),
    "tentacle_sphere": lambda: tentacle_sphere(4),
    "cad_box": lambda: cad_box(8),
    "bad_triangulation": lambda: bad_triangulation(),
}
