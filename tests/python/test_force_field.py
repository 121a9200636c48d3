"""penalty.PenaltyForceField alone: forces, energy and matrices checked by finite differences
through Python (force = -dE/dx, df = K·dx, B = df/dv)."""
import numpy as np
import pytest
import scipy.sparse

import penalty

RNG = np.random.default_rng(7)


def unit(v):
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def two_sets(n1=5, n2=4, contacts=6):
    """Random point sets and contacts, every contact penetrating by 0.05..0.2 m (far from the
    switch at pen = 0, so central differences never cross it)."""
    x1 = RNG.normal(size=(n1, 3))
    x2 = RNG.normal(size=(n2, 3))
    m1 = RNG.integers(0, n1, contacts)
    m2 = RNG.integers(0, n2, contacts)
    normals = unit(RNG.normal(size=(contacts, 3)))
    gap = np.einsum("ij,ij->i", x2[m2] - x1[m1], normals)
    dist = gap + RNG.uniform(0.05, 0.2, contacts)
    ks = RNG.uniform(10.0, 100.0, contacts)
    return x1, x2, m1, m2, normals, dist, ks


def energy(ff, x1, x2):
    ff.add_force(x1, x2)
    return ff.potential_energy()


def test_single_contact_worked_numbers():
    ff = penalty.PenaltyForceField()
    ff.add_contacts([0], [0], [[0.0, 1.0, 0.0]], 0.5, 100.0)
    f1, f2 = ff.add_force(np.array([[0.0, 0.0, 0.0]]), np.array([[0.0, 0.2, 0.0]]))
    # pen = 0.5 − 0.2 = 0.3 m; f2 = ks·pen·n = 30 N along +y, f1 = −f2; E = ½·100·0.3² = 4.5 J
    np.testing.assert_allclose(f2, [[0.0, 30.0, 0.0]], rtol=1e-15)
    np.testing.assert_allclose(f1, [[0.0, -30.0, 0.0]], rtol=1e-15)
    assert ff.potential_energy() == pytest.approx(4.5, rel=1e-15)
    c = ff.contacts()
    assert c["penetration"][0] == pytest.approx(0.3) and c["normal_force"][0] == pytest.approx(30.0)


def test_force_is_minus_energy_gradient():
    x1, x2, m1, m2, normals, dist, ks = two_sets()
    ff = penalty.PenaltyForceField()
    ff.add_contacts(m1, m2, normals, dist, ks)
    f1, f2 = ff.add_force(x1, x2)
    h = 1e-6
    for x, f in ((x1, f1), (x2, f2)):
        grad = np.zeros_like(x)
        for i in range(x.shape[0]):
            for j in range(3):
                x[i, j] += h
                ep = energy(ff, x1, x2)
                x[i, j] -= 2 * h
                em = energy(ff, x1, x2)
                x[i, j] += h
                grad[i, j] = (ep - em) / (2 * h)
        np.testing.assert_allclose(f, -grad, atol=1e-6 * np.abs(f).max())


def test_df_is_k_dx_and_matches_finite_differences():
    x1, x2, m1, m2, normals, dist, ks = two_sets()
    ff = penalty.PenaltyForceField()
    ff.add_contacts(m1, m2, normals, dist, ks)
    ff.add_force(x1, x2)
    K = ff.stiffness_matrix(len(x1), len(x2))
    assert isinstance(K, scipy.sparse.csr_matrix) and K.shape == (3 * (len(x1) + len(x2)),) * 2
    dx1, dx2 = RNG.normal(size=x1.shape), RNG.normal(size=x2.shape)
    df1, df2 = ff.add_dforce(dx1, dx2)
    kdx = K @ np.concatenate([dx1.ravel(), dx2.ravel()])
    np.testing.assert_allclose(np.concatenate([df1.ravel(), df2.ravel()]), kdx, rtol=1e-12, atol=1e-12)
    # K = df/dx by central differences of the forces
    h = 1e-6
    fp1, fp2 = ff.add_force(x1 + h * dx1, x2 + h * dx2)
    fm1, fm2 = ff.add_force(x1 - h * dx1, x2 - h * dx2)
    fd = np.concatenate([(fp1 - fm1).ravel(), (fp2 - fm2).ravel()]) / (2 * h)
    np.testing.assert_allclose(kdx, fd, atol=1e-6 * np.abs(kdx).max())
    # SOFA's sign: K is symmetric negative semi-definite
    dense = K.toarray()
    np.testing.assert_allclose(dense, dense.T, atol=1e-12)
    assert np.linalg.eigvalsh(dense).max() < 1e-9
    # k_factor scales
    half1, _ = ff.add_dforce(dx1, dx2, k_factor=0.5)
    np.testing.assert_allclose(half1, 0.5 * df1, rtol=1e-14)


def test_damping_matrix_is_df_dv():
    x1, x2, m1, m2, normals, dist, ks = two_sets()
    ff = penalty.PenaltyForceField(damping=3.0)
    ff.add_contacts(m1, m2, normals, dist, ks)
    v1, v2 = 0.01 * RNG.normal(size=x1.shape), 0.01 * RNG.normal(size=x2.shape)
    ff.add_force(x1, x2, v1, v2)
    B = ff.damping_matrix(len(x1), len(x2))
    dv1, dv2 = RNG.normal(size=x1.shape), RNG.normal(size=x2.shape)
    h = 1e-6
    fp1, fp2 = ff.add_force(x1, x2, v1 + h * dv1, v2 + h * dv2)
    fm1, fm2 = ff.add_force(x1, x2, v1 - h * dv1, v2 - h * dv2)
    fd = np.concatenate([(fp1 - fm1).ravel(), (fp2 - fm2).ravel()]) / (2 * h)
    bdv = B @ np.concatenate([dv1.ravel(), dv2.ravel()])
    np.testing.assert_allclose(bdv, fd, atol=1e-6 * np.abs(bdv).max())
    assert np.abs(bdv).max() > 0
    db1, db2 = ff.add_dforce(dv1, dv2, k_factor=0.0, b_factor=1.0)
    np.testing.assert_allclose(np.concatenate([db1.ravel(), db2.ravel()]), bdv, rtol=1e-12, atol=1e-12)


def test_same_state_layout():
    x = RNG.normal(size=(6, 3))
    m1, m2 = np.array([0, 1, 2]), np.array([3, 4, 5])
    normals = unit(RNG.normal(size=(3, 3)))
    dist = np.einsum("ij,ij->i", x[m2] - x[m1], normals) + 0.1
    ff = penalty.PenaltyForceField()
    ff.add_contacts(m1, m2, normals, dist, 50.0)
    f = ff.add_force(x)
    assert f.shape == (6, 3)
    np.testing.assert_allclose(f.sum(axis=0), 0.0, atol=1e-12)  # action = reaction
    K = ff.stiffness_matrix(6)
    dx = RNG.normal(size=x.shape)
    np.testing.assert_allclose(ff.add_dforce(dx).ravel(), K @ dx.ravel(), rtol=1e-12, atol=1e-12)


def test_friction_sticking_force_is_gradient_of_spring_energy():
    # one contact, sticking: tangential spring kt = ks, xi = P·(u − u0); E = ½ks·pen² + ½kt·|xi|²
    ff = penalty.PenaltyForceField(friction=True, time_step=0.01)
    ff.add_contacts([0], [0], [[0.0, 1.0, 0.0]], 0.5, 100.0, mu_s=1.0, mu_v=1.0)
    x1 = np.zeros((1, 3))
    x2 = np.array([[0.0, 0.2, 0.0]])
    ff.add_force(x1, x2)  # anchors the spring
    moved = x2 + [[0.01, 0.0, 0.0]]
    f1, f2 = ff.add_force(x1, moved)
    # |kt·xi| = 1 N ≤ mu·f_n = 30 N: sticking, f_t = −kt·xi = −1 N along x
    np.testing.assert_allclose(f2, [[-1.0, 30.0, 0.0]], rtol=1e-12)
    assert ff.contacts()["friction_state"][0] == 1
    assert ff.potential_energy() == pytest.approx(0.5 * 100 * 0.3**2 + 0.5 * 100 * 0.01**2, rel=1e-12)


def test_invalid_arguments_raise_value_error_with_the_library_message():
    ff = penalty.PenaltyForceField()
    with pytest.raises(ValueError, match="stiffness"):
        ff.add_contacts([0], [0], [[0.0, 1.0, 0.0]], 0.1, -1.0)
    with pytest.raises(ValueError, match="normal"):
        ff.add_contacts([0], [0], [[0.0, 2.0, 0.0]], 0.1, 1.0)
    with pytest.raises(ValueError):
        penalty.PenaltyForceField(damping=-1.0)
    with pytest.raises(ValueError, match="expected shape"):
        ff.add_force(np.zeros((2, 2)), np.zeros((2, 3)))
    ff.add_contacts([5], [0], [[0.0, 1.0, 0.0]], 0.1, 1.0)
    with pytest.raises(ValueError):
        ff.add_force(np.zeros((2, 3)), np.zeros((2, 3)))  # DOF 5 outside a 2-point state
