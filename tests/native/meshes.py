"""Named test meshes built in numpy (DESIGN.md §5), shared by tests and benchmarks.

Every function returns ``(V, F)``: V float64 (n, 3) positions, F int32 (m, 3)
0-based vertex indices. Closed meshes are oriented counter-clockwise seen from
outside (outward normals, positive signed volume). Everything is deterministic
(seeded RNGs), so a failing assertion names a reproducible mesh.

Closed genus-0 families: icosphere, noisy_blob, tentacle_sphere, limb_blob
(straight or bent: two poses of one shape), box, cad_box, two_boss_part and
bumps_and_pits (asymmetric features, any resolution: feature matching),
bad_triangulation, sized_sphere_mesh (benchmarks). Broken families (error
paths): open_disc, torus, two_spheres, non_manifold_edge, pinched_spheres,
flipped_face, loose_vertex, nan_vertex, out_of_range_index, zero_area_face.

Open surfaces for feature cut-and-paste: plane_grid, bump_plane (Gaussian
bump), rib_plane (ring-shaped rib), bump_sphere (radial Gaussian bump).
Curved paste targets (closed genus 0) where a feature's exponential map
folds: scan_like (a noisy, bumpy blob like a raw scan, any size) and
cartoon_head (ears, nose, brows and eye sockets: steep, high-curvature forms).
"""
import numpy as np

_ICOSAHEDRON_F = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9],
                           [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2],
                           [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
                           [8, 6, 7], [9, 8, 1]], dtype=np.int64)


def _icosahedron():
    t = (1.0 + 5 ** 0.5) / 2.0
    V = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
                  [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]],
                 dtype=np.float64)
    return V / np.linalg.norm(V, axis=1, keepdims=True), _ICOSAHEDRON_F.copy()


# --- closed genus 0 ---------------------------------------------------------------

def icosphere(subdivisions=2):
    """Unit icosphere: 20 * 4**subdivisions faces."""
    V, F = _icosahedron()
    for _ in range(subdivisions):
        V, F = subdivide(V, F)
        V /= np.linalg.norm(V, axis=1, keepdims=True)
    return V, F.astype(np.int32)


def subdivide(V, F):
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


def geodesic_sphere(frequency):
    """Unit sphere from the icosahedron with every face split into frequency**2
    triangles (20 * frequency**2 faces, any integer frequency, not just powers
    of two). Shared edge points are welded on exact integer barycentric keys."""
    n = int(frequency)
    if n < 1:
        raise ValueError("frequency must be >= 1")
    V0, F0 = _icosahedron()
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    keep = i + j <= n
    i, j = i[keep], j[keep]                      # lattice points of one face
    local = -np.ones((n + 1, n + 1), np.int64)
    local[i, j] = np.arange(len(i))
    ids = np.repeat(F0, len(i), axis=0).reshape(20, len(i), 3)          # (20, P, 3)
    weights = np.broadcast_to(np.stack([n - i - j, i, j], 1), ids.shape)  # (20, P, 3)
    ids = np.where(weights > 0, ids, -1).reshape(-1, 3)
    weights = weights.reshape(-1, 3)
    order = np.argsort(ids, axis=1, kind="stable")
    ids = np.take_along_axis(ids, order, 1)
    weights = np.take_along_axis(weights, order, 1)
    keys = np.concatenate([ids, weights], 1)
    unique, first, weld = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    weld = weld.reshape(-1)
    V = (weights[first, :, None] * V0[np.maximum(ids[first], 0)]).sum(1) / n
    V /= np.linalg.norm(V, axis=1, keepdims=True)
    # Up triangles (i,j),(i+1,j),(i,j+1) and down triangles (i+1,j),(i+1,j+1),(i,j+1):
    # both keep the orientation of the icosahedron face.
    ui, uj = np.nonzero(np.add.outer(np.arange(n), np.arange(n)) <= n - 1)
    di, dj = np.nonzero(np.add.outer(np.arange(n), np.arange(n)) <= n - 2)
    tri = np.concatenate([np.stack([local[ui, uj], local[ui + 1, uj], local[ui, uj + 1]], 1),
                          np.stack([local[di + 1, dj], local[di + 1, dj + 1], local[di, dj + 1]], 1)])
    P = len(i)
    F = (tri[None, :, :] + P * np.arange(20)[:, None, None]).reshape(-1, 3)
    return V, weld[F].astype(np.int32)


def _blob(V, seed, amplitude=0.12, waves=6):
    """Star-shaped, smooth, non-convex: the unit-sphere points V pushed along
    their own direction by a sum of low-frequency waves, then stretched. The
    radius stays >= 1 - waves * amplitude > 0, so nothing self-intersects."""
    rng = np.random.default_rng(seed)
    r = np.ones(len(V))
    for _ in range(waves):
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        r += amplitude * np.cos(3.0 * (V @ direction) + rng.uniform(0, 2 * np.pi))
    return V * r[:, None] * np.array([1.0, 1.3, 0.8])


def noisy_blob(subdivisions=3, seed=0):
    """Icosphere pushed by smooth random low-frequency radial noise (non-convex, star-shaped)."""
    V, F = icosphere(subdivisions)
    return _blob(V, seed), F


def coarse_octopus(subdivisions=2, limbs=6):
    """A coarse octopus (as blend_samples' octopus at low resolution): a
    sphere with `limbs` drooping tentacles pulled out of a few vertices each,
    so their triangles are long and thin (negative cotangent weights)."""
    V, F = icosphere(subdivisions)
    P = V / np.linalg.norm(V, axis=1, keepdims=True)
    angles = 2 * np.pi * np.arange(limbs) / limbs
    D = np.stack([np.cos(angles), np.sin(angles), np.full(limbs, -0.35)], axis=1)
    D /= np.linalg.norm(D, axis=1, keepdims=True)
    pull = np.clip((P @ D.T - 0.9) / 0.1, 0.0, None).max(axis=1)
    out = P * (1.0 + 2.2 * pull[:, None] ** 1.5)
    out[:, 2] -= 0.3 * pull ** 2
    return out, F


def tentacle_directions(tentacles=6, seed=1):
    """Unit axes of tentacle_sphere's fingers: a Fibonacci sphere (evenly
    spread, so fingers never meet) turned by a seeded random rotation."""
    k = np.arange(tentacles) + 0.5
    z = 1.0 - 2.0 * k / tentacles
    phi = np.pi * (1.0 + 5 ** 0.5) * k
    D = np.stack([np.sqrt(1 - z * z) * np.cos(phi), np.sqrt(1 - z * z) * np.sin(phi), z], 1)
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return D @ q.T


def tentacle_sphere(subdivisions=4, tentacles=6, length=4.0, seed=1, cut_angle=0.2):
    """A unit sphere with `tentacles` long thin fingers (extremities, thesis 3.5.1).

    Around each axis the sphere's faces within `cut_angle` are removed and the
    hole is extruded into a tube of about 0.8 * sin(cut_angle) radius (0.16 by
    default: ~6x thinner than the body) that runs `length` body radii out,
    tapers a little and ends in a rounded tip. The tube is meshed ring by ring
    with as many vertices per ring as the hole's rim, and rings spaced 1.5x
    the spacing around, so its triangles stay well shaped however long it is.
    Each finger lies in a cylinder of the rim's radius around its own axis and
    the axes are spread apart, so the surface does not self-intersect.
    """
    V, F = icosphere(subdivisions)
    V = list(V)
    F = np.asarray(F, np.int64)
    axes = tentacle_directions(tentacles, seed)
    if tentacles > 1:
        cos_sep = np.clip(axes @ axes.T - 2 * np.eye(tentacles), -1, 1).max()
        if np.arccos(cos_sep) < 3 * cut_angle:
            raise ValueError("too many tentacles for this cut_angle: fingers would touch")
    new_faces = []
    for d in axes:
        P = np.asarray(V)
        centroid_cos = (P[F].mean(axis=1) / np.linalg.norm(P[F].mean(axis=1), axis=1)[:, None]) @ d
        cut = centroid_cos > np.cos(cut_angle)
        rim = _hole_loop(F[~cut], F[cut])      # runs clockwise around d seen from outside
        F = F[~cut]
        # Frame around the axis; azimuth of each rim vertex, unwrapped.
        e1 = np.cross(d, [1.0, 0, 0] if abs(d[0]) < 0.9 else [0, 1.0, 0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(d, e1)
        R = P[rim]
        angles = np.unwrap(np.arctan2(R @ e2, R @ e1))
        turn = np.sign(angles[-1] - angles[0])  # -1: clockwise about d
        k = len(rim)
        # Later rings: evenly spread azimuths in the rim's order and phase.
        phase = np.mean(angles - turn * 2 * np.pi * np.arange(k) / k)
        az = phase + turn * 2 * np.pi * np.arange(k) / k
        around = np.cos(az)[:, None] * e1 + np.sin(az)[:, None] * e2
        rim_radius = np.linalg.norm(R - np.outer(R @ d, d), axis=1).min()
        radius = 0.8 * np.sin(cut_angle)
        step = 1.5 * 2 * np.pi * radius / k
        heights = np.arange(step, length - radius, step)
        prev = list(rim)
        for s in heights:
            taper = 1.0 - 0.35 * s / length
            fillet = (rim_radius - radius) * np.exp(-s / (2 * step))  # flares into the body
            ring_r = radius * taper + max(fillet, 0.0)
            ring = np.arange(len(V), len(V) + k)
            V.extend(d * (1.0 + s) + ring_r * around)
            new_faces += _ring_strip(prev, ring)
            prev = list(ring)
        # Rounded tip: a quarter circle of rings, then a fan to the apex.
        tip_r = radius * (1.0 - 0.35 * heights[-1] / length)
        tip_rings = max(2, int(np.ceil(0.5 * np.pi * tip_r / step)))
        for t in range(1, tip_rings):
            a = 0.5 * np.pi * t / tip_rings
            ring = np.arange(len(V), len(V) + k)
            V.extend(d * (1.0 + heights[-1] + tip_r * np.sin(a)) + tip_r * np.cos(a) * around)
            new_faces += _ring_strip(prev, ring)
            prev = list(ring)
        apex = len(V)
        V.append(d * (1.0 + heights[-1] + tip_r))
        new_faces += [[prev[(i + 1) % k], prev[i], apex] for i in range(k)]
    F = np.concatenate([F, np.asarray(new_faces, np.int64).reshape(-1, 3)])
    return _compact(np.asarray(V), F)


def _hole_loop(kept, removed):
    """Ordered vertices of the single boundary loop left in `kept` faces where
    the connected disc `removed` is cut out, following kept faces' orientation."""
    half = np.concatenate([kept[:, [0, 1]], kept[:, [1, 2]], kept[:, [2, 0]]])
    cut = {tuple(e) for e in np.concatenate([removed[:, [1, 0]], removed[:, [2, 1]], removed[:, [0, 2]]])}
    nxt = {int(a): int(b) for a, b in half if (int(a), int(b)) in cut}
    start = min(nxt)
    loop = [start]
    while nxt[loop[-1]] != start:
        loop.append(nxt[loop[-1]])
        if len(loop) > len(nxt):
            raise ValueError("cut region is not a disc")
    if len(loop) != len(nxt):
        raise ValueError("cut region is not a disc")
    return np.array(loop)


def _ring_strip(lower, upper):
    """Faces joining two rings of equal length whose lower edges run
    lower[i] -> lower[i+1] in the faces below (so we use them reversed)."""
    k = len(lower)
    faces = []
    for i in range(k):
        j = (i + 1) % k
        faces.append([lower[j], lower[i], upper[i]])
        faces.append([lower[j], upper[i], upper[j]])
    return faces


def _compact(V, F):
    """Drops unused vertices and renumbers."""
    used = np.unique(F)
    remap = -np.ones(len(V), np.int64)
    remap[used] = np.arange(len(used))
    return V[used].astype(np.float64), remap[F].astype(np.int32)


def limb_blob(subdivisions=3, limbs=1, bend_degrees=0.0, length=1.5, cut_angle=0.45, seed=1):
    """A unit sphere with `limbs` stout fingers: tentacle_sphere with short,
    thick tubes (radius about 0.8 * sin(cut_angle), 0.35 by default), one
    closed genus-0 surface. bend_degrees > 0 bends every limb near its root
    (bend_limb), giving a second pose of the same shape; subdivisions sets the
    resolution of body and limbs alike."""
    V, F = tentacle_sphere(subdivisions, tentacles=limbs, length=length, seed=seed,
                           cut_angle=cut_angle)
    if bend_degrees:
        for axis in tentacle_directions(limbs, seed):
            V = bend_limb(V, axis, root=1.15, bend_length=0.8, degrees=bend_degrees)
    return V, F


def bend_limb(V, axis, root, bend_length, degrees):
    """Bends the part of a limb beyond `root` along unit `axis` (points with
    V @ axis > root) like a finger joint: over the next `bend_length` the
    centre line follows a circular arc turning by `degrees` and each cross
    section turns with it (Barr's bend), beyond it the rest of the limb moves
    rigidly. The centre line keeps its length; the arc's radius
    bend_length / angle must exceed the limb's radius, or the inner side folds."""
    d = np.asarray(axis, np.float64) / np.linalg.norm(axis)
    e = np.cross(d, [0.0, 0.0, 1.0] if abs(d[2]) < 0.9 else [1.0, 0.0, 0.0])
    e /= np.linalg.norm(e)
    b = np.cross(d, e)
    theta = np.radians(degrees)
    R = bend_length / theta
    t, u, w = V @ d, V @ e, V @ b
    s = t - root
    phi = theta * np.clip(s, 0.0, bend_length) / bend_length
    beyond = np.maximum(s - bend_length, 0.0)
    centre = (root * d + (R * np.sin(phi))[:, None] * d + (R * (1 - np.cos(phi)))[:, None] * e
              + beyond[:, None] * (np.cos(phi)[:, None] * d + np.sin(phi)[:, None] * e))
    bent = (centre + u[:, None] * (np.cos(phi)[:, None] * e - np.sin(phi)[:, None] * d)
            + w[:, None] * b)
    return np.where((s > 0)[:, None], bent, V)


def protrusion(length=3.0, bend_degrees=0.0, subdivisions=4):
    """A long protrusion as an artist selects it to copy: a unit sphere with one
    tube closed at its tip (tentacle_sphere, cut_angle 0.3: about 0.47 wide,
    `length` long), and the selection of the tube's faces with a ring of the
    sphere around its root. bend_degrees bends the tube near its root
    (bend_limb: 60 a horn, 150 a trunk hanging back along the body).
    Returns V, F, selected face indices, length / width."""
    V, F = tentacle_sphere(subdivisions, tentacles=1, length=length, cut_angle=0.3)
    d = tentacle_directions(1, 1)[0]
    if bend_degrees:
        V = bend_limb(V, d, root=1.25, bend_length=1.2, degrees=bend_degrees)
    C = V[F].mean(axis=1)
    cosine = (C / np.linalg.norm(C, axis=1)[:, None]) @ d
    selection = np.flatnonzero((cosine > np.cos(0.45)) | (np.linalg.norm(C, axis=1) > 1.05))
    return V, F, selection.astype(np.int32), length / (2 * 0.8 * np.sin(0.3))


def box(cells=4, half_extents=(1.0, 1.0, 1.0)):
    """Closed box [-h, h] (h = half_extents) whose six sides are cells x cells
    grids of two triangles each, welded on an integer lattice; outward faces.
    Its convex hull is the box itself, whatever the cells."""
    n = int(cells)
    corners = []
    for a in range(3):
        b, c = (a + 1) % 3, (a + 2) % 3          # e_b x e_c = e_a
        i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
        i, j = i.ravel(), j.ravel()
        for side in (0, 1):
            p00 = np.zeros((len(i), 3), np.int64)
            p00[:, a], p00[:, b], p00[:, c] = side * n, i, j
            du, dv = np.eye(3, dtype=np.int64)[b], np.eye(3, dtype=np.int64)[c]
            p10, p11, p01 = p00 + du, p00 + du + dv, p00 + dv
            if side:
                corners += [np.stack([p00, p10, p11], 1), np.stack([p00, p11, p01], 1)]
            else:
                corners += [np.stack([p00, p11, p10], 1), np.stack([p00, p01, p11], 1)]
    lattice = np.concatenate(corners)
    unique, weld = np.unique(lattice.reshape(-1, 3), axis=0, return_inverse=True)
    V = (2.0 * unique / n - 1.0) * np.asarray(half_extents, np.float64)
    return V, weld.reshape(-1, 3).astype(np.int32)


def _welded_patches(patches, box, k, alternate_diagonals=False):
    """Triangulates integer-lattice rectangle patches (origin, du, dv, nu, nv,
    skip-cell test; outward normal du x dv), two triangles per cell (with
    alternate_diagonals, every other cell split along its other diagonal),
    welds equal corners and centres the box (nx, ny, nz) cells / k."""
    corners = []
    for origin, du, dv, nu, nv, skip in patches:
        i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
        i, j = i.ravel(), j.ravel()
        p00 = origin + np.outer(i, du) + np.outer(j, dv)
        if skip is not None:
            keep = ~skip(p00)
            i, j, p00 = i[keep], j[keep], p00[keep]
        p10, p11, p01 = p00 + du, p00 + du + dv, p00 + dv
        other = ((i + j) % 2 == 1)[:, None, None] if alternate_diagonals else False
        corners += [np.where(other, np.stack([p00, p10, p01], 1), np.stack([p00, p10, p11], 1)),
                    np.where(other, np.stack([p10, p11, p01], 1), np.stack([p00, p11, p01], 1))]
    lattice = np.concatenate(corners)                      # (m, 3 corners, 3 coords), integers
    unique, weld = np.unique(lattice.reshape(-1, 3), axis=0, return_inverse=True)
    V = (unique - np.array(box) / 2.0) / k
    return V.astype(np.float64), weld.reshape(-1, 3).astype(np.int32)


def cad_box(cells_per_unit=8, boss_height=0.25):
    """A CAD-like part: a 2 x 1.4 x 1 box with a rectangular boss standing
    `boss_height` on its top face. Every face is planar and axis-aligned, all
    edges are sharp 90° (convex on the box and boss, concave at the boss's
    foot). Faces are regular grids of `cells_per_unit` cells per unit, built
    on an integer lattice so the walls weld exactly to the top face."""
    k = int(cells_per_unit)
    nx, ny, nz = 2 * k, 2 * int(round(0.7 * k)), k
    bx0, bx1, by0, by1 = nx // 4, nx - nx // 4, ny // 4, ny - ny // 4
    bh = max(1, int(round(boss_height * k)))
    X, Y, Z = np.eye(3, dtype=np.int64)
    o = np.zeros(3, np.int64)
    in_boss = lambda p: (bx0 <= p[:, 0]) & (p[:, 0] < bx1) & (by0 <= p[:, 1]) & (p[:, 1] < by1)  # noqa: E731
    patches = [  # (origin, du, dv, nu, nv, skip-cell test); outward normal = du x dv
        (o, Y, X, ny, nx, None),                      # bottom, -z
        (nz * Z, X, Y, nx, ny, in_boss),              # top, +z, boss footprint cut out
        (o, X, Z, nx, nz, None),                      # front, -y
        (ny * Y, Z, X, nz, nx, None),                 # back, +y
        (o, Z, Y, nz, ny, None),                      # left, -x
        (nx * X, Y, Z, ny, nz, None),                 # right, +x
        (bx0 * X + by0 * Y + (nz + bh) * Z, X, Y, bx1 - bx0, by1 - by0, None),  # boss top
        (bx0 * X + by0 * Y + nz * Z, X, Z, bx1 - bx0, bh, None),                # boss front
        (bx0 * X + by1 * Y + nz * Z, Z, X, bh, bx1 - bx0, None),                # boss back
        (bx0 * X + by0 * Y + nz * Z, Z, Y, bh, by1 - by0, None),                # boss left
        (bx1 * X + by0 * Y + nz * Z, Y, Z, by1 - by0, bh, None),                # boss right
    ]
    return _welded_patches(patches, (nx, ny, nz), k)


def two_boss_part(cells_per_unit=8, alternate_diagonals=False):
    """A CAD-like part with no symmetry: a 2 x 1.5 x 1 box with a 0.75 x 0.5
    boss 0.25 high off-centre on its top and a 0.5 x 0.5 boss 0.5 high
    off-centre on its +x side. All faces planar and axis-aligned, sharp 90°
    edges. cells_per_unit (a multiple of 4) sets the grid; with
    alternate_diagonals every other cell is split along its other diagonal,
    so two calls give the same surface triangulated differently."""
    k = int(cells_per_unit)
    if k < 4 or k % 4:
        raise ValueError("cells_per_unit must be a positive multiple of 4")
    nx, ny, nz = 2 * k, 3 * k // 2, k
    tx0, tx1, ty0, ty1, th = k // 4, k, k // 2, k, k // 4                      # top boss
    sy0, sy1, sz0, sz1, sh = k // 4, 3 * k // 4, k // 4, 3 * k // 4, k // 2    # side boss
    X, Y, Z = np.eye(3, dtype=np.int64)
    o = np.zeros(3, np.int64)
    on_top = lambda p: (tx0 <= p[:, 0]) & (p[:, 0] < tx1) & (ty0 <= p[:, 1]) & (p[:, 1] < ty1)  # noqa: E731
    on_side = lambda p: (sy0 <= p[:, 1]) & (p[:, 1] < sy1) & (sz0 <= p[:, 2]) & (p[:, 2] < sz1)  # noqa: E731
    t0, s0 = tx0 * X + ty0 * Y + nz * Z, nx * X + sy0 * Y + sz0 * Z
    patches = [  # (origin, du, dv, nu, nv, skip-cell test); outward normal = du x dv
        (o, Y, X, ny, nx, None), (nz * Z, X, Y, nx, ny, on_top), (o, X, Z, nx, nz, None),
        (ny * Y, Z, X, nz, nx, None), (o, Z, Y, nz, ny, None), (nx * X, Y, Z, ny, nz, on_side),
        (t0 + th * Z, X, Y, tx1 - tx0, ty1 - ty0, None),             # top boss: cap, 4 walls
        (t0, X, Z, tx1 - tx0, th, None), (t0 + (ty1 - ty0) * Y, Z, X, th, tx1 - tx0, None),
        (t0, Z, Y, th, ty1 - ty0, None), (t0 + (tx1 - tx0) * X, Y, Z, ty1 - ty0, th, None),
        (s0 + sh * X, Y, Z, sy1 - sy0, sz1 - sz0, None),             # side boss: cap, 4 walls
        (s0, X, Z, sh, sz1 - sz0, None), (s0 + (sy1 - sy0) * Y, Z, X, sz1 - sz0, sh, None),
        (s0, Y, X, sy1 - sy0, sh, None), (s0 + (sz1 - sz0) * Z, X, Y, sh, sy1 - sy0, None),
    ]
    return _welded_patches(patches, (nx, ny, nz), k, alternate_diagonals)


BUMPS_AND_PITS = [  # (direction, angular width in radians, radial height): > 0 bump, < 0 pit
    ((0.2, 0.3, 1.0), 0.35, 0.45), ((1.0, -0.2, 0.1), 0.30, 0.35), ((-0.6, 0.8, -0.3), 0.40, -0.30),
    ((0.1, -1.0, -0.5), 0.30, -0.25), ((-0.8, -0.4, 0.5), 0.25, 0.30)]


def bumps_and_pits(sphere=None):
    """A blob with three bumps and two pits of different sizes at irregular
    places (no symmetry), stretched by (1, 1.2, 0.9). The radius is a
    function of the direction only, so any tessellation of the unit sphere
    (`sphere` = (V, F), default icosphere(4); e.g. geodesic_sphere(n), or a
    turned icosphere) gives the same surface, sampled differently."""
    V, F = icosphere(4) if sphere is None else sphere
    P = V / np.linalg.norm(V, axis=1, keepdims=True)
    r = np.ones(len(P))
    for direction, width, height in BUMPS_AND_PITS:
        d = np.asarray(direction) / np.linalg.norm(direction)
        r += height * np.exp(-(np.arccos(np.clip(P @ d, -1, 1)) / width) ** 2)
    return P * r[:, None] * np.array([1.0, 1.2, 0.9]), np.asarray(F, np.int32)


def bad_triangulation(seed=2, splits=80):
    """Closed genus 0 with slivers, very obtuse angles and mixed sizes.

    The convex hull of points spread very unevenly on the unit sphere (a dense
    band, a sparse scatter and a near-collinear line: faces from tiny to huge),
    stretched into an ellipsoid; then `splits` edges are split very unevenly
    (at 1-4% of their length), each leaving a sliver with an angle near 0°
    and one near 180° minus the old corner angle."""
    rng = np.random.default_rng(seed)
    dense = rng.normal(size=(400, 3)) * np.array([0.15, 0.15, 1.0])
    sparse = rng.normal(size=(60, 3))
    line = np.stack([np.linspace(-1, 1, 80), 0.02 * rng.normal(size=80), np.ones(80)], 1)
    P = np.concatenate([dense, sparse, line])
    P /= np.linalg.norm(P, axis=1, keepdims=True)
    F = _orient_outward(P, _convex_hull(P))
    V = list(P * np.array([2.0, 1.0, 0.6]))
    for _ in range(splits):
        f, c = int(rng.integers(len(F))), int(rng.integers(3))
        a, b = F[f, c], F[f, (c + 1) % 3]
        t = rng.uniform(0.01, 0.04)
        m = len(V)
        V.append((1 - t) * V[a] + t * V[b])   # on the chord: the split faces stay flat
        # Both faces of edge (a, b): (u, v, w) with {u, v} = {a, b} becomes
        # (u, m, w) + (m, v, w), keeping the orientation.
        added = []
        for k in range(3):
            u, v, w = F[:, k], F[:, (k + 1) % 3], F[:, (k + 2) % 3]
            for g in np.nonzero(((u == a) & (v == b)) | ((u == b) & (v == a)))[0]:
                added.append([m, v[g], w[g]])
                F[g] = [u[g], m, w[g]]
        F = np.concatenate([F, np.array(added, np.int64)])
    return _compact(np.asarray(V, np.float64), F)


def _convex_hull(P):
    """Incremental 3D convex hull (O(n^2), vectorized per point; fine for test
    sizes). Points on a sphere are all extreme, so every point ends up a vertex."""
    n = len(P)
    i0, i1 = 0, 1
    i2 = next(i for i in range(2, n) if np.linalg.norm(np.cross(P[i1] - P[i0], P[i] - P[i0])) > 1e-9)
    i3 = next(i for i in range(3, n)
              if abs(np.dot(np.cross(P[i1] - P[i0], P[i2] - P[i0]), P[i] - P[i0])) > 1e-9)
    F = np.array([[i0, i1, i2], [i0, i2, i3], [i0, i3, i1], [i1, i3, i2]], np.int64)
    inward = np.einsum("ij,ij->i", _normals(P, F), P[F[:, 0]] - P[[i0, i1, i2, i3]].mean(axis=0)) < 0
    F[inward] = F[inward][:, [0, 2, 1]]
    for p in range(n):
        if p in (i0, i1, i2, i3):
            continue
        visible = np.einsum("ij,ij->i", _normals(P, F), P[p] - P[F[:, 0]]) > 1e-12
        if not visible.any():
            continue
        seen = {(int(a), int(b)) for f in F[visible] for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
        horizon = [(a, b, p) for (a, b) in seen if (b, a) not in seen]
        F = np.concatenate([F[~visible], np.array(horizon, np.int64)])
    return F


def _normals(V, F):
    return np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])


def _orient_outward(V, F):
    """Flips faces whose normal points towards the centroid (convex shapes only)."""
    c = V.mean(axis=0)
    a, b, d = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    n = np.cross(b - a, d - a)
    flip = np.einsum("ij,ij->i", n, (a + b + d) / 3 - c) < 0
    F = F.copy()
    F[flip] = F[flip][:, [0, 2, 1]]
    return F


def sized_sphere_mesh(target_faces):
    """Closed genus-0 blob with about `target_faces` faces (for benchmarks):
    a geodesic sphere of the frequency n whose 20 n^2 faces come closest
    (10k -> 9680, 100k -> 100820, 400k -> 397620), deformed like noisy_blob.
    Triangles are near-uniform at every size, so timings scale with size only."""
    frequency = max(1, int(round((target_faces / 20.0) ** 0.5)))
    V, F = geodesic_sphere(frequency)
    return _blob(V, seed=7), F


def signed_volume(V, F):
    """Enclosed volume; positive when the faces point outwards."""
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


# --- broken meshes for the error paths ----------------------------------------------

def open_disc():
    """Icosphere with a cap cut off: one boundary loop."""
    V, F = icosphere(2)
    keep = V[F].mean(axis=1)[:, 2] < 0.3
    return _compact(V, F[keep])


def torus(n=16, m=8, R=1.0, r=0.35):
    """Closed, genus 1."""
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
    """Two separate closed spheres: 2 components."""
    V, F = icosphere(1)
    return np.vstack([V, V + [3.0, 0, 0]]), np.vstack([F, F + len(V)]).astype(np.int32)


def non_manifold_edge():
    """A sphere plus a fin: one extra triangle on an existing edge (3 faces there)."""
    V, F = icosphere(1)
    a, b = F[0, 0], F[0, 1]
    V = np.vstack([V, [[2.0, 2.0, 2.0]]])
    F = np.vstack([F, [[a, b, len(V) - 1]]]).astype(np.int32)
    return V, F


def pinched_spheres():
    """Two closed spheres sharing exactly one vertex (0): every edge has two
    faces, but vertex 0 has two separate fans (a non-manifold vertex)."""
    V, F = icosphere(1)
    n = len(V)
    antipode = int(np.argmin(np.linalg.norm(V + V[0], axis=1)))
    V2 = V + 2 * V[0]                      # its antipode of vertex 0 lands on vertex 0
    F2 = F + n
    F2[F2 == n + antipode] = 0
    return _compact(np.vstack([V, V2]), np.vstack([F, F2]))


def flipped_face(face=5):
    """Closed genus-0 icosphere with one face turned inside out."""
    V, F = icosphere(2)
    F = F.copy()
    F[face] = F[face, [0, 2, 1]]
    return V, F


def loose_vertex():
    """Closed genus-0 icosphere plus one vertex used by no face (the last one)."""
    V, F = icosphere(1)
    return np.vstack([V, [[0.0, 0.0, 3.0]]]), F


def nan_vertex():
    """NaN in the y coordinate of vertex 5."""
    V, F = icosphere(1)
    V = V.copy()
    V[5, 1] = np.nan
    return V, F


def out_of_range_index():
    """Face 7 refers to vertex len(V) + 10."""
    V, F = icosphere(1)
    F = F.copy()
    F[7, 2] = len(V) + 10
    return V, F


def zero_area_face():
    """Closed genus 0 where face 10 has zero area: one of its corners moved
    onto the midpoint of the opposite edge."""
    V, F = icosphere(2)
    V = V.copy()
    a, b, c = F[10]
    V[c] = 0.5 * (V[a] + V[b])
    return V, F


FAMILIES_CLOSED = {
    "icosphere": lambda: icosphere(3),
    "noisy_blob": lambda: noisy_blob(3, seed=0),
    "tentacle_sphere": lambda: tentacle_sphere(4),
    "cad_box": lambda: cad_box(10),
    "bad_triangulation": lambda: bad_triangulation(),
}

FAMILIES_BROKEN = {
    "open_disc": open_disc,
    "torus": torus,
    "two_spheres": two_spheres,
    "non_manifold_edge": non_manifold_edge,
    "pinched_spheres": pinched_spheres,
    "flipped_face": flipped_face,
    "loose_vertex": loose_vertex,
    "zero_area_face": zero_area_face,
}


# --- open surfaces and bumps for feature cut-and-paste -------------------------------

def plane_grid(n=60, half=1.0):
    """(n+1)**2 vertices on [-half, half]**2 at z = 0, 2 n**2 faces counter-clockwise seen from +z."""
    x = np.linspace(-half, half, n + 1)
    X, Y = np.meshgrid(x, x, indexing="ij")
    V = np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)])
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    a = (i * (n + 1) + j).ravel()
    b = a + n + 1
    F = np.concatenate([np.stack([a, b, b + 1], 1), np.stack([a, b + 1, a + 1], 1)])
    return V, F.astype(np.int32)


def face_centroids(V, F):
    return V[F].mean(axis=1)


def bump_plane(n=60, height=0.1, sigma=0.3, radius=0.9):
    """plane_grid with z = height exp(-r**2 / sigma**2) where r < radius; also returns the
    faces whose centroid lies within radius (the feature): (V, F, feature_faces)."""
    V, F = plane_grid(n)
    r = np.linalg.norm(V[:, :2], axis=1)
    V[:, 2] = np.where(r < radius, height * np.exp(-r ** 2 / sigma ** 2), 0.0)
    rc = np.linalg.norm(face_centroids(V, F)[:, :2], axis=1)
    return V, F, np.flatnonzero(rc < radius).astype(np.int32)


def rib_plane(n=60, height=0.08, width=0.08, ring=0.5):
    """plane_grid with a ring-shaped rib z = height exp(-(r - ring)**2 / width**2) where
    |r - ring| < 3 width; the rib's faces (an annulus) returned too: (V, F, feature_faces)."""
    V, F = plane_grid(n)
    r = np.linalg.norm(V[:, :2], axis=1)
    V[:, 2] = np.where(np.abs(r - ring) < 3 * width, height * np.exp(-(r - ring) ** 2 / width ** 2), 0.0)
    rc = np.linalg.norm(face_centroids(V, F)[:, :2], axis=1)
    return V, F, np.flatnonzero(np.abs(rc - ring) < 3 * width).astype(np.int32)


def bump_sphere(subdivisions=5, height=0.05, sigma=0.2, cap=0.6):
    """Unit icosphere pushed out radially by 1 + height exp(-theta**2 / sigma**2), theta the
    angle from +z, where theta < cap; with the faces whose centroid has theta < cap:
    (V, F, feature_faces)."""
    V, F = icosphere(subdivisions)
    theta = np.arccos(np.clip(V[:, 2], -1, 1))
    V = V * np.where(theta < cap, 1 + height * np.exp(-theta ** 2 / sigma ** 2), 1.0)[:, None]
    c = face_centroids(V, F)
    tc = np.arccos(np.clip(c[:, 2] / np.linalg.norm(c, axis=1), -1, 1))
    return V, F, np.flatnonzero(tc < cap).astype(np.int32)


# --- curved paste targets -----------------------------------------------------------

def _radial_bumps(P, bumps):
    """1 + sum of height * exp(-(angle to direction / width)**2) over (direction, width, height)."""
    r = np.ones(len(P))
    for direction, width, height in bumps:
        d = np.asarray(direction, np.float64)
        d /= np.linalg.norm(d)
        r += height * np.exp(-(np.arccos(np.clip(P @ d, -1, 1)) / width) ** 2)
    return r


def scan_like(target_faces=100000, seed=3, bumps=80, noise=0.6):
    """A raw scan's surface (closed genus 0, about `target_faces` faces): the
    sized_sphere_mesh blob (low-frequency waves) with `bumps` random Gaussian
    bumps and dents (angular widths 0.04-0.2 rad, heights +-(0.02-0.12)) and
    per-vertex radial noise of `noise` times the mean edge length, like a
    scanner's. Deterministic for a seed."""
    frequency = max(1, int(round((target_faces / 20.0) ** 0.5)))
    P, F = geodesic_sphere(frequency)
    rng = np.random.default_rng(seed)
    directions = rng.normal(size=(bumps, 3))
    widths = rng.uniform(0.04, 0.2, bumps)
    heights = rng.uniform(0.02, 0.12, bumps) * rng.choice([-1.0, 1.0], bumps)
    V = _blob(P * _radial_bumps(P, zip(directions, widths, heights))[:, None], seed=7)
    edge = np.linalg.norm(V[F[:, 0]] - V[F[:, 1]], axis=1).mean()
    V += (noise * edge * rng.normal(size=len(V)))[:, None] * P
    return V, F


CARTOON_FORMS = [  # (direction, angular width, height): +y is the face's front, +z up
    ((0.0, 1.0, -0.05), 0.14, 0.45),     # nose
    ((0.12, 1.0, -0.22), 0.04, -0.06),   # nostrils
    ((-0.12, 1.0, -0.22), 0.04, -0.06),
    ((0.95, 0.0, 0.3), 0.09, 0.7),       # ears: tall and thin
    ((-0.95, 0.0, 0.3), 0.09, 0.7),
    ((0.35, 0.85, 0.35), 0.11, -0.16),   # eye sockets with eyeballs in them
    ((-0.35, 0.85, 0.35), 0.11, -0.16),
    ((0.35, 0.85, 0.35), 0.05, 0.12),
    ((-0.35, 0.85, 0.35), 0.05, 0.12),
    ((0.3, 0.8, 0.55), 0.06, 0.10),      # brows
    ((-0.3, 0.8, 0.55), 0.06, 0.10),
    ((0.0, 0.9, -0.42), 0.07, 0.08),     # lips
    ((0.0, 0.85, -0.52), 0.07, 0.07),
    ((0.0, 0.75, -0.65), 0.25, 0.15),    # chin
    ((0.0, 0.2, 1.0), 0.35, 0.20),       # crown
]


def cartoon_head(subdivisions=5, jitter=0.35, noise=0.0, seed=5):
    """A cartoon head (closed genus 0, 20 * 4**subdivisions faces): an
    icosphere pushed out into a nose, two tall thin ears, eyeballs, brows,
    lips, a chin and a crown, and in at the nostrils and eye sockets (radial
    Gaussians, so it stays star-shaped), stretched to (0.9, 1, 1.1). The forms are steep: where they
    meet the skull the surface turns sharply. The triangulation is irregular
    like a modelled mesh's: before the push every vertex moves along the
    sphere in a random direction by up to `jitter` times its shortest edge
    (seeded; below half the distance to any opposite edge, so no face turns
    over and the surface does not cross itself). noise: radial noise of that
    many mean edge lengths, as on a scanned or sculpted head."""
    P, F = icosphere(subdivisions)
    rng = np.random.default_rng(seed)
    edges = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    length = np.linalg.norm(P[edges[:, 0]] - P[edges[:, 1]], axis=1)
    shortest = np.full(len(P), np.inf)
    np.minimum.at(shortest, edges[:, 0], length)
    np.minimum.at(shortest, edges[:, 1], length)
    J = rng.normal(size=P.shape)
    J -= np.einsum("ij,ij->i", J, P)[:, None] * P
    J *= (jitter * shortest * rng.uniform(0, 1, len(P)) / np.linalg.norm(J, axis=1))[:, None]
    P = P + J
    P /= np.linalg.norm(P, axis=1, keepdims=True)
    V = P * _radial_bumps(P, CARTOON_FORMS)[:, None]
    edge = np.linalg.norm(V[F[:, 0]] - V[F[:, 1]], axis=1).mean()
    V += (noise * edge * rng.normal(size=len(V)))[:, None] * P
    return V * np.array([0.9, 1.0, 1.1]), F


def star(arms=8, aspect=20.0, subdivisions=4, seed=1):
    """A ball with `arms` thin arms, each `aspect` times as long as it is
    wide (tentacle_sphere's fingers): the long-limbed characters whose
    conformal sphere map shrinks the arms geometrically to rounding (issue 28)."""
    cut_angle = 0.2 if arms <= 12 else 0.15
    width = 2 * 0.8 * np.sin(cut_angle)
    return tentacle_sphere(subdivisions, tentacles=arms, length=aspect * width, seed=seed, cut_angle=cut_angle)


def coiled_tube(turns=3.0, radius=0.12, coil_radius=1.0, pitch=0.45, around=12):
    """A closed tube coiled along a helix with rounded ends (a snake, a
    tail, a telephone cord): about turns * 2 pi * coil_radius / (2 radius)
    times as long as it is wide (78 by default), its ends near each other in
    space and far apart on the surface."""
    step = 2 * np.pi * radius / around  # rings about as far apart as the points around
    length = turns * 2 * np.pi * np.hypot(coil_radius, pitch / (2 * np.pi))
    theta = np.linspace(0.0, 2 * np.pi * turns, int(np.ceil(length / step)) + 1)
    c = np.stack([coil_radius * np.cos(theta), coil_radius * np.sin(theta), pitch * theta / (2 * np.pi)], 1)
    tangent = np.stack([-coil_radius * np.sin(theta), coil_radius * np.cos(theta),
                        np.full_like(theta, pitch / (2 * np.pi))], 1)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    normal = np.stack([-np.cos(theta), -np.sin(theta), np.zeros_like(theta)], 1)  # towards the axis
    binormal = np.cross(tangent, normal)
    az = 2 * np.pi * np.arange(around) / around
    V, F, rings = [], [], []
    # A rounded cap at each end: rings shrinking on a quarter circle, then an apex.
    cap = 4
    def ring_at(center, t, n, b, r):
        rings.append(np.arange(len(V), len(V) + around))
        V.extend(center + r * (np.cos(az)[:, None] * n + np.sin(az)[:, None] * b))
    for k in range(cap, 0, -1):
        a = 0.5 * np.pi * k / (cap + 1)
        ring_at(c[0] - radius * np.sin(a) * tangent[0], tangent[0], normal[0], binormal[0], radius * np.cos(a))
    for i in range(len(theta)):
        ring_at(c[i], tangent[i], normal[i], binormal[i], radius)
    for k in range(1, cap + 1):
        a = 0.5 * np.pi * k / (cap + 1)
        ring_at(c[-1] + radius * np.sin(a) * tangent[-1], tangent[-1], normal[-1], binormal[-1], radius * np.cos(a))
    for lower, upper in zip(rings[:-1], rings[1:]):
        for i in range(around):
            j = (i + 1) % around
            F += [[lower[i], lower[j], upper[j]], [lower[i], upper[j], upper[i]]]
    start = len(V)
    V.append(c[0] - radius * tangent[0])
    end = len(V)
    V.append(c[-1] + radius * tangent[-1])
    first, last = rings[0], rings[-1]
    F += [[start, first[(i + 1) % around], first[i]] for i in range(around)]
    F += [[end, last[i], last[(i + 1) % around]] for i in range(around)]
    V, F = np.asarray(V, np.float64), np.asarray(F, np.int64)
    if signed_volume(V, F) < 0:
        F = F[:, ::-1]
    return V, F.astype(np.int32)
