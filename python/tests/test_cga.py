"""cgamesh.cga: algebra identities, versors against matrices, batched forms against single ones,
and the mapping to the `clifford` package's conformalize(Cl(3)) layout on hand-written tables."""

import numpy as np
import pytest

import cgamesh
from cgamesh import cga

RNG = np.random.default_rng(18)

# clifford's conformalize(Cl(3)) blade order, written out by hand.
CLIFFORD_NAMES = ["1", "e1", "e2", "e3", "e4", "e5",
                  "e12", "e13", "e14", "e15", "e23", "e24", "e25", "e34", "e35", "e45",
                  "e123", "e124", "e125", "e134", "e135", "e145", "e234", "e235", "e245", "e345",
                  "e1234", "e1235", "e1245", "e1345", "e2345", "e12345"]


def random_mv():
    return cga.Multivector(RNG.normal(size=32))


def test_value_is_a_writable_view():
    x = cga.Multivector()
    v = x.value
    assert v.shape == (32,) and v.dtype == np.float64
    v[3] = 2.5
    assert x["e1^e2"] == 2.5 and x[3] == 2.5
    assert np.shares_memory(v, x.value)
    assert cga.blade_names[3] == "e1^e2" and cga.blade_names[24] == "einf^eo" and cga.blade_names[31] == "e1^e2^e3^einf^eo"


def test_basis_metric():
    assert (cga.e1 * cga.e1).scalar() == 1
    assert (cga.einf * cga.einf).value.tolist() == [0.0] * 32
    assert (cga.eo | cga.einf).scalar() == -1
    assert (cga.e4 * cga.e4).scalar() == 1 and (cga.e5 * cga.e5).scalar() == -1
    np.testing.assert_allclose((cga.e4 * cga.e5).value, (cga.einf ^ cga.eo).value)
    np.testing.assert_allclose((cga.e4 + cga.e5).value, cga.einf.value)


def test_products_and_identities():
    a, b, c = random_mv(), random_mv(), random_mv()
    np.testing.assert_allclose(((a * b) * c).value, (a * (b * c)).value, atol=1e-9)
    np.testing.assert_allclose((a * a.inv()).value, cga.Multivector(1.0).value, atol=1e-9)
    np.testing.assert_allclose((~(a * b)).value, ((~b) * (~a)).value, atol=1e-9)
    x, y = cga.e1 + 2 * cga.e3, cga.e2 - cga.einf
    np.testing.assert_allclose((x * y).value, ((x | y) + (x ^ y)).value, atol=1e-12)
    np.testing.assert_allclose((x << (x ^ y)).value, ((x | x) * y - (x | y) * x).value, atol=1e-12)
    for k in range(6):
        g = a.grade(k)
        assert all(len(n.split("^")) == k or (k == 0 and n == "1") for n, v in zip(cga.blade_names, g.value) if v)
    np.testing.assert_allclose(sum((a.grade(k) for k in range(6)), cga.Multivector()).value, a.value)
    np.testing.assert_allclose(a.dual().undual().value, a.value, atol=1e-12)
    with pytest.raises(cgamesh.InvalidInputError):
        cga.einf.inv()


def rotation_matrix(axis, angle):
    u = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    return np.cos(angle) * np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * np.outer(u, u)


def test_versors_match_matrices():
    x = np.array([0.3, -1.2, 2.0])
    np.testing.assert_allclose(cga.down(cga.up(x)), x, atol=1e-12)
    axis, angle = [1, 2, -0.5], 0.8
    r = cga.rotor(axis, angle)
    np.testing.assert_allclose(cga.down(cga.sandwich(r, cga.up(x))), rotation_matrix(axis, angle) @ x, atol=1e-12)
    t = cga.translator([1, 2, 3])
    np.testing.assert_allclose(cga.down(cga.sandwich(t, cga.up(x))), x + [1, 2, 3], atol=1e-12)
    d = cga.dilator(2.5)
    np.testing.assert_allclose(cga.down(cga.sandwich(d, cga.up(x))), 2.5 * x, atol=1e-12)
    v = t * r * d
    np.testing.assert_allclose(cga.down(cga.sandwich(v, cga.up(x))),
                               2.5 * rotation_matrix(axis, angle) @ x + [1, 2, 3], atol=1e-12)
    # exp and log invert each other; blends hit their ends.
    np.testing.assert_allclose(cga.exp(cga.log(v)).value, v.value / np.sqrt((v * ~v).scalar()), atol=1e-10)
    np.testing.assert_allclose(cga.log_blend(t, v, 0.0).value, t.value, atol=1e-12)
    np.testing.assert_allclose(cga.lerp(t, v, 1.0).value, v.value, atol=1e-12)
    # Spheres and planes: X·S = 0 on them.
    s = cga.sphere([0, 0, 1], 2.0)
    assert abs((cga.up([0, 0, 3]) | s).scalar()) < 1e-12
    p = cga.plane([0, 0, 2], 1.0)
    assert abs((cga.up([5, -4, 0.5]) | p).scalar()) < 1e-12  # n·x = d with n normalised: z = 0.5
    with pytest.raises(cgamesh.InvalidInputError):
        cga.rotor([0, 0, 0], 1.0)
    with pytest.raises(cgamesh.InvalidInputError):
        cga.down(cga.einf)


def test_batched_forms_equal_single_forms():
    pts = RNG.normal(size=(200, 3))
    up = cga.up(pts)
    assert up.shape == (200, 32) and up.dtype == np.float64
    for i in (0, 17, 199):
        np.testing.assert_array_equal(up[i], cga.up(pts[i]).value)
    np.testing.assert_allclose(cga.down(up), pts, atol=1e-12)
    v = cga.translator([0.5, 0, -1]) * cga.rotor([0, 1, 0], 0.3) * cga.dilator(0.7)
    moved = cga.sandwich(v, up)
    assert moved.shape == (200, 32)
    for i in (0, 99):
        np.testing.assert_allclose(moved[i], cga.sandwich(v, cga.up(pts[i])).value, atol=1e-12)
    expected = 0.7 * pts @ rotation_matrix([0, 1, 0], 0.3).T + [0.5, 0, -1]
    np.testing.assert_allclose(cga.down(moved), expected, atol=1e-12)
    with pytest.raises(cgamesh.InvalidInputError):
        cga.up(np.zeros((4, 2)))


def test_clifford_layout_names():
    assert cga.clifford_blade_names == CLIFFORD_NAMES


@pytest.mark.parametrize("ours, theirs", [
    # up((1, 2, 3)) = x + 7 einf + eo: e4 = 7 - 1/2, e5 = 7 + 1/2.
    (lambda: cga.up([1, 2, 3]), {"e1": 1, "e2": 2, "e3": 3, "e4": 6.5, "e5": 7.5}),
    (lambda: cga.einf, {"e4": 1, "e5": 1}),
    (lambda: cga.eo, {"e4": -0.5, "e5": 0.5}),
    (lambda: cga.e4, {"e4": 1}),
    (lambda: cga.e5, {"e5": 1}),
    (lambda: cga.einf ^ cga.eo, {"e45": 1}),
    (lambda: cga.e1 ^ cga.einf, {"e14": 1, "e15": 1}),
    (lambda: cga.e2 ^ cga.eo, {"e24": -0.5, "e25": 0.5}),
    (lambda: cga.e1 ^ cga.e2 ^ cga.einf ^ cga.eo, {"e1245": 1}),
    (lambda: cga.I, {"e12345": 1}),
    # translator(t) = 1 - t einf / 2.
    (lambda: cga.translator([2, 0, -4]), {"1": 1, "e14": -1, "e15": -1, "e34": 2, "e35": 2}),
    # dilator(4) = (1 + 4)/(2·2) + (1 - 4)/(2·2) einf^eo.
    (lambda: cga.dilator(4.0), {"1": 1.25, "e45": -0.75}),
    # rotor about z by 90°: cos 45° - sin 45° e12.
    (lambda: cga.rotor([0, 0, 1], np.pi / 2), {"1": np.sqrt(0.5), "e12": -np.sqrt(0.5)}),
])
def test_clifford_coefficient_tables(ours, theirs):
    mv = ours()
    expected = np.zeros(32)
    for name, value in theirs.items():
        expected[CLIFFORD_NAMES.index(name)] = value
    np.testing.assert_allclose(cga.to_clifford(mv.value), expected, atol=1e-12)
    np.testing.assert_allclose(cga.from_clifford(expected), mv.value, atol=1e-12)


@pytest.mark.parametrize("a, b, product", [
    ("e4", "e5", {"e45": 1}),
    ("e5", "e4", {"e45": -1}),
    ("e45", "e45", {"1": 1}),
    ("e12", "e12", {"1": -1}),
    ("e1", "e45", {"e145": 1}),
    ("e5", "e5", {"1": -1}),
    ("e12345", "e12345", {"1": -1}),
])
def test_clifford_products(a, b, product):
    def blade(name):
        v = np.zeros(32)
        v[CLIFFORD_NAMES.index(name)] = 1
        return cga.Multivector(cga.from_clifford(v))

    expected = np.zeros(32)
    for name, value in product.items():
        expected[CLIFFORD_NAMES.index(name)] = value
    np.testing.assert_allclose(cga.to_clifford((blade(a) * blade(b)).value), expected, atol=1e-12)


def test_batched_clifford_mapping():
    values = RNG.normal(size=(10, 32))
    theirs = cga.to_clifford(values)
    assert theirs.shape == (10, 32)
    np.testing.assert_allclose(cga.from_clifford(theirs), values, atol=1e-12)
    np.testing.assert_allclose(theirs[3], cga.to_clifford(values[3]))
