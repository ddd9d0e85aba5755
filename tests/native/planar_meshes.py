"""Open test patches for the planar solver: (V float64 (n,3), F int32 (m,3)),
counter-clockwise faces. Deterministic."""
import numpy as np

import meshes


def _polar_disc(rings, sectors, height, squash=1.0):
    pts = [[0.0, 0.0]]
    for r in range(1, rings + 1):
        phi = 2 * np.pi * (np.arange(sectors) + 0.5 * r) / sectors
        rho = r / rings
        pts += list(np.stack([rho * np.cos(phi), squash * rho * np.sin(phi)], 1))
    P = np.asarray(pts)
    idx = lambda r, s: 0 if r == 0 else 1 + (r - 1) * sectors + s % sectors  # noqa: E731
    F = [[0, idx(1, s), idx(1, s + 1)] for s in range(sectors)]
    for r in range(1, rings):
        for s in range(sectors):
            F += [[idx(r, s), idx(r + 1, s), idx(r + 1, s + 1)], [idx(r, s), idx(r + 1, s + 1), idx(r, s + 1)]]
    V = np.column_stack([P, height(P[:, 0], P[:, 1])])
    return V, np.asarray(F, dtype=np.int32)


def bumpy_disc(rings=12, sectors=48):
    return _polar_disc(rings, sectors, lambda x, y: 0.25 * np.cos(3 * x) * np.sin(4 * y))


def hemisphere_cap(subdivisions=3):
    V, F = meshes.icosphere(subdivisions)
    keep = V[F].mean(axis=1)[:, 2] > -0.05
    return _compact(V, F[keep])


def long_strip(n=60, m=4):
    i, j = np.meshgrid(np.arange(n + 1), np.arange(m + 1), indexing="ij")
    x, y = i.ravel() / m, j.ravel() / m
    V = np.column_stack([x, y, 0.3 * np.sin(x)])
    idx = lambda a, b: a * (m + 1) + b  # noqa: E731
    F = []
    for a in range(n):
        for b in range(m):
            F += [[idx(a, b), idx(a + 1, b), idx(a + 1, b + 1)], [idx(a, b), idx(a + 1, b + 1), idx(a, b + 1)]]
    return V, np.asarray(F, dtype=np.int32)


def disc_with_hole(rings=10, sectors=40):
    V, F = _polar_disc(rings, sectors, lambda x, y: 0.2 * x * y)
    inner = np.linalg.norm(V[F].mean(axis=1)[:, :2], axis=1) < 0.3
    return _compact(V, F[~inner])


def noisy_sphere_patch():
    V, F = meshes.noisy_blob(3, seed=9)
    c = V[F].mean(axis=1)
    keep = c[:, 0] > 0.1 * np.linalg.norm(c, axis=1).max()
    return _compact(V, F[keep])


def badly_shaped_disc():
    return _polar_disc(10, 60, lambda x, y: 0.3 * x ** 2, squash=0.15)


def _compact(V, F):
    used = np.unique(F)
    remap = -np.ones(len(V), np.int64)
    remap[used] = np.arange(len(used))
    return V[used], remap[F].astype(np.int32)


FAMILIES = {
    "bumpy_disc": bumpy_disc,
    "hemisphere_cap": hemisphere_cap,
    "long_strip": long_strip,
    "disc_with_hole": disc_with_hole,
    "noisy_sphere_patch": noisy_sphere_patch,
    "badly_shaped_disc": badly_shaped_disc,
}
