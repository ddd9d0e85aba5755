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


def whole_turn(source, target):
    """The best rotation (columns) taking the centred source onto the centred
    target (Kabsch, vertices weighted alike)."""
    P = np.asarray(source) - np.mean(source, axis=0)
    Q = np.asarray(target) - np.mean(target, axis=0)
    U, _, Vt = np.linalg.svd(Q.T @ P)
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt))])
    return U @ D @ Vt


def rotation(axis, degrees):
    """The rotation (columns) by `degrees` about `axis` (Rodrigues)."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    a = np.radians(degrees)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K


def rotation_power(R, t):
    """R turned by t of its angle (about its own axis)."""
    angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
    if angle < 1e-12:
        return np.eye(3)
    axis = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / (2 * np.sin(angle))
    return rotation(axis, np.degrees(t * angle))


def inverted_share_turning(source, target, positions, F, t):
    """inverted_share with the ends carried to t by the whole shape's turn
    (G(t) on the source's normals, G(t) G^-1 on the target's): a shape
    turning by nearly half a turn as a whole is not turned over half way,
    though its faces are near a right angle from both ends' own normals."""
    G = whole_turn(source, target)
    n0 = face_normals(source, F) @ rotation_power(G, t).T
    n1 = face_normals(target, F) @ (rotation_power(G, t) @ G.T).T
    n = face_normals(positions, F)
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
