"""atmosh.sh against closed forms of the real orthonormal SH (Condon-Shortley phase) and
against `atmosh sh rotate / irradiance / eval` on the same coefficient CSV."""

import io
import math

import numpy as np
import pandas as pd
import pytest

import atmosh

SH = atmosh.sh
C1 = math.sqrt(3.0 / (4.0 * math.pi))  # band-1 normalisation


def _random_dirs(n, seed=3):
    v = np.random.default_rng(seed).normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def test_evaluate_band_0_and_1_closed_forms():
    d = _random_dirs(20)
    y = SH.evaluate(2, d)
    assert y.shape == (20, 4)
    np.testing.assert_allclose(y[:, 0], 0.5 / math.sqrt(math.pi), rtol=1e-15)
    # Y_1-1 = -C1 y, Y_10 = C1 z, Y_11 = -C1 x (Condon-Shortley phase; basis.hpp)
    np.testing.assert_allclose(y[:, 1], -C1 * d[:, 1], rtol=1e-14, atol=1e-16)
    np.testing.assert_allclose(y[:, 2], C1 * d[:, 2], rtol=1e-14, atol=1e-16)
    np.testing.assert_allclose(y[:, 3], -C1 * d[:, 0], rtol=1e-14, atol=1e-16)
    assert SH.evaluate(3, np.zeros((0, 3))).shape == (0, 9)
    assert SH.evaluate(3, [[0.0, 0.0, 1.0]]).shape == (1, 9)
    c = np.ones((2, 9))
    assert SH.reconstruct(c, np.zeros((0, 3))).shape == (0, 2)
    assert SH.irradiance_at(c, np.zeros((0, 3))).shape == (0, 2)
    assert SH.irradiance_at(c[0], [[0.0, 0.0, 1.0]]).shape == (1,)


def test_grid_analysis_and_projections_of_known_functions():
    # f = 1 + 2 z: c_0 = sqrt(4 pi), c_(1,0) = 2 / C1, everything else 0.
    expect = np.zeros(16)
    expect[0] = math.sqrt(4 * math.pi)
    expect[2] = 2.0 / C1
    g = SH.grid(4)
    vals = 1.0 + 2.0 * g["directions"][..., 2]
    np.testing.assert_allclose(SH.analyse(vals, 4), expect, atol=1e-13)
    np.testing.assert_allclose(SH.synthesise(expect, nlat=vals.shape[0], nphi=vals.shape[1]), vals, atol=1e-13)
    # FFTW's measured plans (nphi = 12: a factor 3) give the same transforms to rounding
    g12 = SH.grid(4, nphi=12)
    v12 = 1.0 + 2.0 * g12["directions"][..., 2]
    np.testing.assert_allclose(SH.analyse(v12, 4, fft="measure"), expect, atol=1e-13)
    np.testing.assert_allclose(SH.synthesise(expect, nlat=4, nphi=12, fft="measure"), v12, atol=1e-13)
    with pytest.raises(atmosh.InputError, match="fft: 'patient'"):
        SH.analyse(v12, 4, fft="patient")
    # the same function as an equirect image (rows from +z) and a cube map, two channels
    H, W = 16, 32
    theta = math.pi * (np.arange(H) + 0.5) / H
    img = np.repeat((1.0 + 2.0 * np.cos(theta))[:, None], W, axis=1)
    two = np.stack([img, 3.0 * img], axis=-1)
    c = SH.project_equirect(two, 4)
    assert c.shape == (2, 16)
    np.testing.assert_allclose(c[0], expect, atol=1e-12)
    np.testing.assert_allclose(c[1], 3.0 * expect, atol=1e-12)
    cube = 1.0 + 2.0 * SH.cube_directions(32)[..., 2]
    cc = SH.project_cube(cube, 2)
    # texel sums with exact solid angles: the constant exactly, the linear term to the texel size
    assert cc[0] == pytest.approx(expect[0], rel=1e-6)
    assert cc[2] == pytest.approx(expect[2], rel=2e-3)
    r = SH.render_equirect(expect, W, H)
    np.testing.assert_allclose(r, img, rtol=1e-6)


def test_rotation_irradiance_energy_windows():
    c = np.zeros(9)
    c[2] = 1.0  # a z lobe
    # R maps z to x: the lobe then points along x (active rotation).
    R = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])
    rc = SH.rotate(c, matrix=R)
    assert SH.reconstruct(rc, [1.0, 0.0, 0.0]) == pytest.approx(SH.reconstruct(c, [0.0, 0.0, 1.0]), rel=1e-14)
    np.testing.assert_allclose(SH.band_energy(rc), SH.band_energy(c), atol=1e-15)
    # Ry(pi/2) as z-y-z Euler angles gives the same rotation
    np.testing.assert_allclose(SH.rotate(c, euler_zyz=(0.0, math.pi / 2, 0.0)), rc, atol=1e-15)
    # constant radiance L: irradiance pi L at every normal
    L = np.zeros(9)
    L[0] = 2.0 * math.sqrt(4 * math.pi)
    np.testing.assert_allclose(SH.irradiance_at(L, _random_dirs(5)), 2.0 * math.pi, rtol=1e-14)
    np.testing.assert_allclose(SH.irradiance_factors(5)[:5], [math.pi, 2 * math.pi / 3, math.pi / 4, 0.0,
                                                              -math.pi / 24], atol=1e-14)
    # Hanning window (Sloan 2008): w_l = (1 + cos(pi l / L)) / 2
    np.testing.assert_allclose(SH.window("hanning", 6), (1 + np.cos(np.pi * np.arange(6) / 6)) / 2, rtol=1e-14)
    assert SH.apply_window(np.ones(9), "none").tolist() == np.ones(9).tolist()


def _write_csv(path, coeffs):
    L = SH.bands_of(coeffs)
    rows = [(l, m, l * (l + 1) + m) for l in range(L) for m in range(-l, l + 1)]
    df = pd.DataFrame(rows, columns=["l", "m", "index"])
    for k, ch in enumerate(np.atleast_2d(coeffs)):
        df["c%d" % k] = ch
    df.to_csv(path, index=False, float_format="%.17g")


def _read_csv(path):
    df = pd.read_csv(path, comment="#")
    return df.iloc[:, 3:].to_numpy().T


def test_rotate_irradiance_eval_match_cli(cli, tmp_path):
    c = np.random.default_rng(7).normal(size=(2, 16))
    f = tmp_path / "c.csv"
    _write_csv(f, c)
    cli.text("sh", "rotate", f, "--euler-zyz", "30,50,70", "-o", tmp_path / "r.csv")
    ref = _read_csv(tmp_path / "r.csv")
    got = SH.rotate(c, euler_zyz=np.radians([30.0, 50.0, 70.0]))
    np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-14)
    cli.text("sh", "irradiance", f, "-o", tmp_path / "e.csv")
    np.testing.assert_allclose(SH.irradiance(c), _read_csv(tmp_path / "e.csv"), rtol=1e-12, atol=1e-14)
    j = cli.json("sh", "eval", f, "--dir", "0.3,-0.4,0.5")
    d = np.array(j["direction"])
    np.testing.assert_allclose(SH.reconstruct(c, d[None, :])[0], [j["values"]["c0"], j["values"]["c1"]], rtol=1e-12)


def test_bad_input():
    with pytest.raises(atmosh.InputError, match="square"):
        SH.band_energy(np.ones(5))
    with pytest.raises(atmosh.InputError, match="bands"):
        SH.evaluate(0, [[0.0, 0.0, 1.0]])
    with pytest.raises(atmosh.InputError):
        SH.evaluate(2, [[0.0, 0.0, 0.0]])
    with pytest.raises(atmosh.InputError, match="exactly one"):
        SH.rotate(np.ones(4))
    with pytest.raises(atmosh.InputError, match="window|hamming"):
        SH.window("hamming", 3)
