"""RBF interpolation of thesis 5.2 (pm.RbfInterpolator): the Python face of
paste/rbf_interpolator. Interpolation at the centres, polynomial reproduction,
Wendland's compact support, solve-many == fresh, typed errors."""
import numpy as np
import pytest

import paramorph_native as pm


def points(n, d=2, seed=0, scale=1.0):
    return np.random.default_rng(seed).uniform(-scale, scale, size=(n, d))


@pytest.mark.parametrize("basis,degree", [("polyharmonic", 1), ("polyharmonic", 2), ("wendland", -1), ("wendland", 1)])
@pytest.mark.parametrize("d", [2, 3])
def test_rbf_interpolates_at_centres(basis, degree, d):
    X = points(200, d, seed=1)
    rbf = pm.RbfInterpolator(X, basis=basis, polynomial_degree=degree, support_radius=1.2)
    f = np.column_stack([np.sin(3 * X[:, 0]), X[:, 1] ** 2 - X[:, 0], np.cos(X.sum(axis=1))])
    c = rbf.solve(f)
    assert c.shape == (200 + rbf.num_polynomial_terms, 3)
    s = rbf.evaluate(X, c)
    assert np.abs(s - f).max() <= 1e-10 * np.abs(f).max()
    # One column in, one column out.
    c0 = rbf.solve(f[:, 0])
    assert c0.shape == (200 + rbf.num_polynomial_terms,)
    assert np.allclose(rbf.evaluate(X, c0), f[:, 0], rtol=0, atol=1e-10)


@pytest.mark.parametrize("degree", [1, 2])
def test_rbf_reproduces_its_polynomials(degree):
    X = points(100, 2, seed=2)
    Y = points(500, 2, seed=3, scale=1.3)
    rbf = pm.RbfInterpolator(X, polynomial_degree=degree)

    def poly(P, k):
        x, y = P[:, 0], P[:, 1]
        v = 0.5 + 0 * x
        if k >= 1:
            v = v + 1.7 * x - 0.4 * y
        if k >= 2:
            v = v + 0.8 * x * x - 1.2 * x * y + 0.3 * y * y
        return v

    for k in range(degree + 1):
        s = rbf.evaluate(Y, rbf.solve(poly(X, k)))
        assert np.abs(s - poly(Y, k)).max() < 1e-9, k


def test_rbf_wendland_is_zero_beyond_support():
    X = points(50, 2, seed=4, scale=0.5)
    h = 0.3
    rbf = pm.RbfInterpolator(X, basis="wendland", polynomial_degree=-1, support_radius=h)
    c = rbf.solve(np.cos(X[:, 0]) + 2.0)
    Y = points(3000, 2, seed=5, scale=2.0)
    s = rbf.evaluate(Y, c)
    nearest = np.linalg.norm(Y[:, None, :] - X[None, :, :], axis=2).min(axis=1)
    far = nearest >= h
    assert far.sum() > 100 and (~far).sum() > 100
    assert np.all(s[far] == 0.0)
    assert np.count_nonzero(s[~far]) > 0.9 * (~far).sum()


def test_rbf_session_solves_like_fresh_interpolators():
    X = points(150, 2, seed=6)
    Y = points(1000, 2, seed=7)
    session = pm.RbfInterpolator(X)
    E = session.evaluation_matrix(Y)
    assert E.shape == (1000, 153)
    rng = np.random.default_rng(8)
    for _ in range(3):
        # Smooth values (what a paste moves): random waves and offsets.
        a, b = rng.normal(size=(2, 3))
        f = np.sin(X[:, :1] * a + X[:, 1:] * b) + rng.normal(size=3)
        fresh = pm.RbfInterpolator(X)
        c = session.solve(f)
        assert np.allclose(c, fresh.solve(f), rtol=1e-12, atol=1e-12 * np.abs(c).max())
        # Round-off of the product grows with the coefficients' size.
        tol = 1e-13 * np.abs(c).max() * E.shape[1]
        assert np.abs(E @ c - fresh.evaluate(Y, fresh.solve(f))).max() <= tol


def test_rbf_errors():
    X = points(20, 2, seed=9)
    dup = X.copy()
    dup[5] = dup[11]
    with pytest.raises(pm.InvalidInputError, match="coincide"):
        pm.RbfInterpolator(dup)
    bad = X.copy()
    bad[2, 0] = np.nan
    with pytest.raises(pm.InvalidInputError):
        pm.RbfInterpolator(bad)
    line = np.column_stack([np.arange(10.0), 3 * np.arange(10.0) - 1])
    with pytest.raises(pm.InvalidInputError, match="unisolvent"):
        pm.RbfInterpolator(line)
    with pytest.raises(pm.InvalidInputError):
        pm.RbfInterpolator(points(10, 4))
    with pytest.raises(pm.InvalidInputError):
        pm.RbfInterpolator(X, basis="gaussian")
    with pytest.raises(pm.InvalidInputError):
        pm.RbfInterpolator(X, basis="wendland")  # no support radius
    with pytest.raises(pm.InvalidInputError):
        pm.RbfInterpolator(X, polynomial_degree=0)  # r^3 needs degree >= 1
    rbf = pm.RbfInterpolator(X)
    with pytest.raises(pm.InvalidInputError):
        rbf.solve(np.zeros((19, 3)))
    with pytest.raises(pm.InvalidInputError):
        rbf.evaluate(points(5, 3), np.zeros((23, 1)))
