"""Open disc patches for the planar benchmark, cut from closed or scanned meshes.

A patch is a face subset of a manifold mesh. Cutting one out (a plane, a BFS
region) easily leaves what isometric_map() rejects or what makes the
comparison unfair: stray islands, interior holes (the region wrapped around
some faces it did not reach) and pinch vertices (two fans of the region
meeting at one vertex). clean_disc() removes all three, so every patch is one
connected, manifold, genus-0 piece with one boundary loop, unless the source
mesh itself has a hole inside the region (a scan hole), which no face subset
can close: fill_holes() closes those first. Callers still check the result
with pm.validate().
"""
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import breadth_first_order, connected_components


def compact(V, F):
    """Drops unreferenced vertices; returns (V, F int32)."""
    used = np.unique(F)
    remap = -np.ones(len(V), np.int64)
    remap[used] = np.arange(len(used))
    return V[used], remap[F].astype(np.int32)


def _edges(F):
    """Per half-edge (3m): sorted vertex pair and owning face."""
    pairs = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]).astype(np.int64)
    return np.sort(pairs, axis=1), np.tile(np.arange(len(F)), 3)


def face_adjacency(F):
    """Sparse symmetric face-face matrix over shared edges (manifold edges only)."""
    key, owner = _edges(F)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, owner = key[order], owner[order]
    same = np.all(key[1:] == key[:-1], axis=1)
    a, b = owner[:-1][same], owner[1:][same]
    m = len(F)
    return coo_matrix((np.ones(2 * len(a)), (np.concatenate([a, b]), np.concatenate([b, a]))),
                      shape=(m, m)).tocsr()


def _components(adjacency, mask):
    """Labels (−1 outside mask) of the edge-connected components of a face subset."""
    idx = np.flatnonzero(mask)
    _, labels = connected_components(adjacency[idx][:, idx], directed=False)
    out = -np.ones(len(mask), np.int64)
    out[idx] = labels
    return out


def _largest(labels):
    counts = np.bincount(labels[labels >= 0])
    return labels == np.argmax(counts)


def _pinch_vertices(F, mask):
    """Vertices where the region's faces form more than one fan.

    In a manifold source mesh the region's faces around a vertex split into
    (faces − region-interior edges) fans, or exactly one closed fan when that
    difference is zero."""
    sub = F[mask]
    n = int(F.max()) + 1
    faces_at = np.bincount(sub.ravel(), minlength=n)
    key, _ = _edges(sub)
    unique, counts = np.unique(key, axis=0, return_counts=True)
    inner = unique[counts == 2]
    edges_at = np.bincount(inner.ravel(), minlength=n)
    return np.flatnonzero(faces_at - edges_at >= 2)


def clean_disc(F, mask, max_rounds=50):
    """Turns a face mask into one piece without interior holes or pinches.

    Repeats until nothing changes: keep the largest component; fill every
    component of the complement except the largest (those are holes the
    region surrounds); drop every region face at a pinch vertex (that merges
    the two sides of the pinch in the complement, and the next fill decides
    whether they were a hole)."""
    adjacency = face_adjacency(F)
    mask = mask.copy()
    for _ in range(max_rounds):
        before = mask.copy()
        mask = _largest(_components(adjacency, mask))
        rest = _components(adjacency, ~mask)
        if (rest >= 0).any():
            mask |= (rest >= 0) & ~_largest(rest)
        pinches = _pinch_vertices(F, mask)
        if pinches.size:
            mask &= ~np.isin(F, pinches).any(axis=1)
        if np.array_equal(mask, before):
            return mask
    raise RuntimeError("clean_disc: region did not settle")


def fill_holes(V, F):
    """Closes every boundary loop of the mesh with a fan around the loop's
    centroid (one new vertex per loop), oriented like the faces around it.

    For scans (the bunny has 5 holes in its base): a large region grown on
    the scan surrounds some hole sooner or later, and no face subset of the
    scan turns that annulus into a disc. The fans are synthetic surface, but
    small (one hole is a few dozen edges)."""
    key, owner = _edges(F)
    unique, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    directed = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    boundary = directed[counts[inverse.reshape(-1)] == 1]
    nxt = dict(zip(boundary[:, 0].tolist(), boundary[:, 1].tolist()))
    V, fans, seen = list(V), [], set()
    for start in nxt:
        if start in seen:
            continue
        loop, v = [], start
        while v not in seen:
            seen.add(v)
            loop.append(v)
            v = nxt[v]
        centre = len(V)
        V.append(np.mean([V[i] for i in loop], axis=0))
        # A boundary edge a→b belongs to a face that runs a→b, so the fan
        # runs b→a to keep the orientation consistent.
        fans += [[loop[(k + 1) % len(loop)], loop[k], centre] for k in range(len(loop))]
    return np.asarray(V), np.vstack([F, np.asarray(fans, np.int32).reshape(-1, 3)]).astype(np.int32)


def half_by_plane(V, F, normal, offset=0.0):
    """Mask of the faces whose centroid lies on the positive side of the plane,
    cleaned to a disc."""
    side = V[F].mean(axis=1) @ np.asarray(normal, float) > offset
    return clean_disc(F, side)


def bfs_region(F, target_faces, seed_face):
    """Mask of the region grown by breadth-first search over face adjacency
    from seed_face until it holds target_faces faces, then cleaned to a disc
    (so its final size differs from the target by what cleaning adds or drops)."""
    order = breadth_first_order(face_adjacency(F), seed_face, directed=False,
                                return_predecessors=False)
    mask = np.zeros(len(F), bool)
    mask[order[:target_faces]] = True
    return clean_disc(F, mask)
