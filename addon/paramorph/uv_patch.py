"""Selected faces as UV patches for the isometric unwrap (thesis ch. 2): the
faces are cut along seams and along the selection's border, each loop gets
the patch vertex it belongs to, and the patch splits into islands (connected
pieces), each mapped on its own. Blender's pinned UVs become hard pins.
numpy only: loops are joined across shared, unseamed edges by label
propagation, not by Python loops over elements."""
import numpy as np


def _int_array(collection, name, count, width=1):
    out = np.empty(count * width, dtype=np.int32)
    collection.foreach_get(name, out)
    return out if width == 1 else out.reshape(count, width)


def _connected_labels(count, pairs):
    """Smallest member of each connected set of 0..count-1 joined by `pairs`."""
    labels = np.arange(count)
    if len(pairs) == 0:
        return labels
    a, b = pairs[:, 0], pairs[:, 1]
    while True:
        low = np.minimum(labels[a], labels[b])
        before = labels.copy()
        np.minimum.at(labels, a, low)
        np.minimum.at(labels, b, low)
        while True:  # pointer jumping: every label points at a root
            jumped = labels[labels]
            if np.array_equal(jumped, labels):
                break
            labels = jumped
        if np.array_equal(labels, before):
            return labels


def uv_pins(mesh, layer):
    """Per-loop pinned flags of a UV layer (3.4: data.pin_uv; 3.5+: layer.pin,
    empty until something is pinned; the legacy data.pin_uv must not be
    touched there, it reads and writes past a pin layer that does not exist)."""
    pins = np.zeros(len(mesh.loops), dtype=bool)
    if hasattr(layer, "pin"):
        if len(layer.pin) == len(mesh.loops):
            layer.pin.foreach_get("value", pins)
    else:
        layer.data.foreach_get("pin_uv", pins)
    return pins


def read_uv(mesh, layer):
    uv = np.empty(2 * len(mesh.loops), dtype=np.float32)
    layer.data.foreach_get("uv", uv)
    return uv.reshape(-1, 2).astype(np.float64)


class Island:
    """One connected patch: V (k,3), F (t,3), the patch vertex of each of its
    loops, and hard pins (indices into V and their UVs)."""

    def __init__(self, V, F, loops, loop_vertex, pinned, pinned_uv):
        self.V, self.F, self.loops, self.loop_vertex = V, F, loops, loop_vertex
        self.pinned, self.pinned_uv = pinned, pinned_uv


def selected_islands(mesh, polygon_mask, uv=None, pins=None):
    """Islands of the polygons in `polygon_mask`, cut at seams (edge.use_seam)
    and at the mask's border. `uv`/`pins`: per-loop UVs and pinned flags of
    the layer being written (pins only count where `pins` is given)."""
    L, P = len(mesh.loops), len(mesh.polygons)
    loop_vertex = _int_array(mesh.loops, "vertex_index", L)
    loop_edge = _int_array(mesh.loops, "edge_index", L)
    loop_start = _int_array(mesh.polygons, "loop_start", P)
    loop_total = _int_array(mesh.polygons, "loop_total", P)
    seam = np.zeros(len(mesh.edges), dtype=bool)
    mesh.edges.foreach_get("use_seam", seam)
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3).astype(np.float64)

    loop_poly = np.repeat(np.arange(P), loop_total)
    rank = np.arange(L) - loop_start[loop_poly]
    next_loop = loop_start[loop_poly] + (rank + 1) % loop_total[loop_poly]
    inside = polygon_mask[loop_poly]

    # Two patch loops on one unseamed edge (opposite directions) join the
    # corners at each end: loop la (a->b) with next(lb) (at a), next(la) with lb.
    candidates = np.flatnonzero(inside & ~seam[loop_edge])
    order = candidates[np.argsort(loop_edge[candidates], kind="stable")]
    edges = loop_edge[order]
    starts = np.flatnonzero(np.r_[True, edges[1:] != edges[:-1]])
    counts = np.diff(np.r_[starts, len(edges)])
    manifold = starts[counts == 2]
    la, lb = order[manifold], order[manifold + 1]
    pairs = np.concatenate([np.stack([la, next_loop[lb]], 1), np.stack([next_loop[la], lb], 1)])
    corner = _connected_labels(L, pairs)  # loops sharing a patch vertex share a label

    mesh.calc_loop_triangles()
    T = len(mesh.loop_triangles)
    tri_loops = _int_array(mesh.loop_triangles, "loops", T, 3)
    tri_poly = _int_array(mesh.loop_triangles, "polygon_index", T)
    tri_loops = tri_loops[polygon_mask[tri_poly]]
    if len(tri_loops) == 0:
        return []
    # Islands: corners joined through their triangles.
    tri_pairs = np.concatenate([tri_loops[:, [0, 1]], tri_loops[:, [1, 2]]])
    island_of_loop = _connected_labels(L, np.concatenate([tri_pairs, np.stack([np.arange(L), corner], 1)]))

    islands = []
    patch_loops = np.flatnonzero(inside)
    for island in np.unique(island_of_loop[patch_loops]):
        loops = patch_loops[island_of_loop[patch_loops] == island]
        corners, first, local = np.unique(corner[loops], return_index=True, return_inverse=True)
        local_of_loop = np.full(L, -1, dtype=np.int64)
        local_of_loop[loops] = local
        tris = tri_loops[island_of_loop[tri_loops[:, 0]] == island]
        V = co[loop_vertex[loops[first]]]
        F = local_of_loop[tris].astype(np.int32)
        pinned = np.zeros(0, dtype=np.int32)
        pinned_uv = np.zeros((0, 2))
        if pins is not None and uv is not None:
            pinned_loops = loops[pins[loops]]
            pinned, where = np.unique(local_of_loop[pinned_loops], return_index=True)
            pinned_uv = uv[pinned_loops[where]]
            pinned = pinned.astype(np.int32)
        islands.append(Island(V, F, loops, local_of_loop[loops], pinned, pinned_uv))
    return islands


def pack_free_islands(results, islands, margin):
    """Islands without pins, laid out on shelves in [0, 1]^2 at one common
    scale (their relative sizes kept); pinned islands stay where the pins are."""
    free = [i for i, island in enumerate(islands) if len(island.pinned) == 0]
    if not free:
        return results
    boxes = [(results[i].min(axis=0), results[i].max(axis=0)) for i in free]
    sizes = np.array([hi - lo for lo, hi in boxes]) + margin
    order = np.argsort(-sizes[:, 1], kind="stable")
    width = max(float(np.sqrt((sizes[:, 0] * sizes[:, 1]).sum())), float(sizes[:, 0].max()))
    x = y = shelf = 0.0
    offsets = np.zeros((len(free), 2))
    for k in order:  # a handful of islands, not mesh elements
        if x > 0 and x + sizes[k, 0] > width:
            x, y, shelf = 0.0, y + shelf, 0.0
        offsets[k] = (x, y)
        x += sizes[k, 0]
        shelf = max(shelf, sizes[k, 1])
    extent = max(float((offsets + sizes).max()), 1e-12)
    out = list(results)
    for k, i in enumerate(free):
        out[i] = (results[i] - boxes[k][0] + offsets[k] + 0.5 * margin) / extent
    return out


def _area(V, F):
    """Total area of triangles F over points V (2 or 3 columns)."""
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    if V.shape[1] == 2:  # written out: NumPy 2 dropped np.cross of 2-vectors
        (ux, uy), (vx, vy) = (b - a).T, (c - a).T
        return 0.5 * float(np.abs(ux * vy - uy * vx).sum())
    return 0.5 * float(np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())


def texel_density(island, layout_uv):
    """UV length per 3D length of the island in the layout it had (per-vertex
    UVs), or None when that layout is degenerate (no layout yet)."""
    surface, flat = _area(island.V, island.F), _area(layout_uv, island.F)
    if not (surface > 0 and flat > 1e-12 * surface and np.isfinite(flat)):
        return None
    return float(np.sqrt(flat / surface))


def place_by_pins(free_uv, island, density):
    """A free (isometric, 3D-sized) map of the island scaled to `density` and
    turned and moved to fit its pins best (least squares): the pins place and
    orient the island, its size comes from the surface (issue 20: two pins
    from a 0-1 layout made the island a sliver, its stretch 150). Returns the
    UVs and the largest distance of a pin from its pinned place."""
    uv = free_uv * density
    P, Q = uv[island.pinned], island.pinned_uv
    if len(P) >= 2:  # the best rotation (Kabsch in 2D, no reflection, no scale)
        p0, q0 = P.mean(axis=0), Q.mean(axis=0)
        H = (P - p0).T @ (Q - q0)
        U, _, Vt = np.linalg.svd(H)
        d = np.sign(np.linalg.det(Vt.T @ U.T)) or 1.0
        R = Vt.T @ np.diag([1.0, d]) @ U.T
        uv = (uv - p0) @ R.T + q0
    else:
        uv = uv - P.mean(axis=0) + Q.mean(axis=0)
    return uv, float(np.linalg.norm(uv[island.pinned] - Q, axis=1).max())
