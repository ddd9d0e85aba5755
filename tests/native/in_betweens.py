"""How good an in-between is (issue 17), shared by tests and benchmarks:
faces turned over against both ends, faces passing through other faces, and
the enclosed volume against the ends'."""
import numpy as np


def face_normals(V, F):
    V = np.asarray(V)
    return np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])


def volume(V, F):
    V = np.asarray(V)
    return float(np.einsum("ij,ij->i", V[F[:, 0]], np.cross(V[F[:, 1]], V[F[:, 2]])).sum() / 6.0)


def inverted_share(source, target, positions, F):
    """Share of faces whose normal at `positions` points against their
    normals at both ends."""
    n0, n1, n = face_normals(source, F), face_normals(target, F), face_normals(positions, F)
    against = (np.einsum("ij,ij->i", n, n0) < 0) & (np.einsum("ij,ij->i", n, n1) < 0)
    return float(against.mean())


def volume_excursion(source, target, frames, F):
    """How far the volumes of the frames (in time order, ends excluded) leave
    the monotone path between the ends' volumes, as a share of the larger
    end's: 0 when each frame's volume lies between its neighbours'."""
    volumes = [volume(source, F)] + [volume(P, F) for P in frames] + [volume(target, F)]
    sign = 1.0 if volumes[-1] >= volumes[0] else -1.0
    worst = 0.0
    for k in range(1, len(volumes)):
        worst = max(worst, sign * (max(volumes[:k]) if sign > 0 else min(volumes[:k])) - sign * volumes[k])
    for k in range(1, len(volumes) - 1):  # and never past the far end
        worst = max(worst, sign * (volumes[k] - volumes[-1]), sign * (volumes[0] - volumes[k]))
    return worst / max(abs(volumes[0]), abs(volumes[-1]))
