"""The model through Python: numbers agree with numpy, errors are the documented classes."""
import math

import numpy as np
import pytest

import ifsforge


def test_contraction_factor_is_the_largest_singular_value():
    rng = np.random.default_rng(1)
    for n in range(2, 9):
        a = rng.uniform(-1, 1, (n, n))
        m = ifsforge.AffineMap(a, rng.uniform(-1, 1, n))
        assert m.contraction_factor() == pytest.approx(np.linalg.svd(a, compute_uv=False)[0], rel=1e-10)
        assert m.determinant() == pytest.approx(np.linalg.det(a), rel=1e-9, abs=1e-12)


def test_params_round_trip_and_eq5():
    m = ifsforge.AffineMap([[0.3, -0.4], [0.5, 0.2]], [1.0, -2.0])
    back = ifsforge.AffineMap.from_params(m.params(2))
    np.testing.assert_allclose(back.matrix, m.matrix, atol=1e-12)
    np.testing.assert_allclose(back.offset, m.offset)
    p = ifsforge.MapParams(dim=2, scale=[0.5, 0.5, 1], rotation=[30, 30, 0])
    c, s = 0.5 * math.cos(math.pi / 6), 0.5 * math.sin(math.pi / 6)
    np.testing.assert_allclose(ifsforge.AffineMap.from_params(p).matrix, [[c, -s], [s, c]], atol=1e-15)


def test_apply_many_points_and_compose():
    m = ifsforge.AffineMap([[0.5, 0], [0, 0.5]], [1, 0])
    pts = np.array([[0.0, 0.0], [2.0, 2.0]])
    np.testing.assert_allclose(m(pts), [[1, 0], [2, 1]])
    np.testing.assert_allclose(m.compose(m.inverse()).matrix, np.eye(2), atol=1e-15)


def test_classification_and_errors():
    half = [[0.5, 0], [0, 0.5]]
    sierpinski = ifsforge.Ifs([ifsforge.AffineMap(half, o) for o in ([0, 0], [0.5, 0], [0.25, 0.5])])
    assert sierpinski.classify() == "hyperbolic"
    np.testing.assert_allclose(sierpinski.probabilities, [1 / 3] * 3)  # Eq. 46, equal determinants
    np.testing.assert_allclose(sierpinski.fixed_points()[1], [1, 0])
    grow = ifsforge.Ifs([ifsforge.AffineMap([[1.3, 0], [0, 1.3]], [0, 0])], name="grow")
    assert grow.classify() == "divergent"
    with pytest.raises(ifsforge.DivergentSystemError, match="grow"):
        ifsforge.render(grow, "chaos", 16)
    with pytest.raises(ValueError):  # InputError is a ValueError
        ifsforge.Ifs([ifsforge.AffineMap(half, [0, 0])], probabilities=[0.0])
    with pytest.raises(ifsforge.InputError, match="NaN"):
        ifsforge.Ifs([ifsforge.AffineMap([[float("nan"), 0], [0, 0.5]], [0, 0])])
    with pytest.raises(ifsforge.InputError, match="layout"):
        ifsforge.Ifs([ifsforge.AffineMap(half, [0, 0])], layout="xyz")


def test_sample_points_lie_on_the_attractor():
    half = [[0.5, 0], [0, 0.5]]
    s = ifsforge.Ifs([ifsforge.AffineMap(half, o) for o in ([0, 0], [1, 0], [0, 1])])  # right-angled gasket
    pts = s.sample_points(50000, seed=3)
    assert pts.shape == (50000, 2)
    np.testing.assert_array_equal(pts, s.sample_points(50000, seed=3))
    # The attractor is the gasket on (0,0), (2,0), (0,2): in units of 2, the binary expansions of
    # x and y never share a 1 bit, so at 2^-8 resolution floor(256 x/2) & floor(256 y/2) == 0.
    x, y = (np.floor(np.clip(pts / 2, 0, 1 - 1e-12) * 256)).astype(int).T
    assert np.mean((x & y) == 0) > 0.999
    assert pts.min() >= -1e-12 and pts.max() <= 2 + 1e-12
