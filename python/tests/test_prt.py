"""atmosh.prt against `atmosh prt bake` (same seed and samples) and the closed forms of
unshadowed diffuse transfer."""

import math

import numpy as np
import pytest

import atmosh


def _read_ply(path):
    """Vertex rows (x y z nx ny nz albedo ao t0 ...) of an ASCII transfer file."""
    lines = open(path).read().splitlines()
    n = next(int(s.split()[2]) for s in lines if s.startswith("element vertex"))
    start = lines.index("end_header") + 1
    return np.array([[float(x) for x in s.split()] for s in lines[start:start + n]])


def test_bake_matches_cli(cli, tmp_path):
    m = atmosh.prt.builtin_scene("sphere-on-plane", 6)
    got = atmosh.prt.bake(m["vertices"], m["triangles"], normals=m["normals"], albedo=m["albedo"], bands=3,
                          strata=10, seed=1, mode="shadowed")
    cli.text("prt", "bake", "--scene-builtin", "sphere-on-plane", "--resolution", 6, "--samples", 100, "--seed", 1,
             "--quiet", "-o", tmp_path / "t.ply")
    ref = _read_ply(tmp_path / "t.ply")
    assert got["transfer"].shape == (len(m["vertices"]), 9) == (len(ref), 9)
    # the file holds 9 significant digits
    np.testing.assert_allclose(got["transfer"], ref[:, 8:], rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(got["ao"], ref[:, 7], rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(m["vertices"], ref[:, :3], rtol=1e-8, atol=1e-9)


def test_unshadowed_transfer_closed_form_and_relight():
    # Unshadowed transfer (albedo/pi) A_l Y_lm(n): band 0 is albedo / (2 sqrt(pi)), band 1
    # (albedo/pi)(2 pi/3) sqrt(3/(4 pi)) (-y, z, -x).
    n = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8]])
    a = 0.7
    t = atmosh.prt.unshadowed_transfer(2, n, a)
    c1 = (a / math.pi) * (2 * math.pi / 3) * math.sqrt(3 / (4 * math.pi))
    np.testing.assert_allclose(t[:, 0], a / (2 * math.sqrt(math.pi)), rtol=1e-14)
    np.testing.assert_allclose(t[:, 1:], c1 * np.stack([-n[:, 1], n[:, 2], -n[:, 0]], axis=1), atol=1e-15)
    # Under constant radiance L a diffuse surface sends out albedo * L.
    light = np.zeros(4)
    light[0] = 5.0 * math.sqrt(4 * math.pi)
    np.testing.assert_allclose(atmosh.prt.relight(t, light), a * 5.0, rtol=1e-14)
    assert atmosh.prt.relight(t, np.stack([light, 2 * light])).shape == (2, 2)
    # a flat quad facing up: the unshadowed bake is that closed form at every vertex
    v = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
    tri = np.array([[0, 1, 2], [0, 2, 3]])
    b = atmosh.prt.bake(v, tri, bands=2, mode="unshadowed", default_albedo=a)
    np.testing.assert_allclose(b["transfer"], np.repeat(t[:1], 4, axis=0), rtol=1e-13, atol=1e-15)
    # shadowed with nothing above: the Monte Carlo estimate of the same (jittered 20 x 20)
    s = atmosh.prt.bake(v, tri, bands=2, mode="shadowed", default_albedo=a, strata=20)
    np.testing.assert_allclose(s["transfer"], b["transfer"], atol=0.02 * t[0, 0])
    np.testing.assert_allclose(s["ao"], 1.0, atol=0.02)


def test_render_interpolates_vertex_values():
    # A unit quad seen from straight above: the image of a linear function of x is linear
    # across the pixels that see it, 2 at the centre, and 0 on the background (the corners,
    # outside the bounding sphere's disc).
    v = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
    tri = np.array([[0, 1, 2], [0, 2, 3]])
    img = atmosh.prt.render(v, tri, 1.0 + 2.0 * v[:, 0], 33, 33, view_dir=(0.0, 0.0, 1.0))
    assert img.shape == (33, 33)
    assert img[16, 16] == pytest.approx(2.0, rel=1e-6)
    assert img[0, 0] == 0.0 and img[32, 32] == 0.0
    row = img[16][img[16] > 0]
    assert len(row) > 10
    np.testing.assert_allclose(np.diff(row, 2), 0.0, atol=1e-5)
    two = atmosh.prt.render(v, tri, np.stack([v[:, 0], v[:, 1]], axis=1), 9, 9, view_dir=(0.0, 0.0, 1.0))
    assert two.shape == (9, 9, 2)


def test_shapes_zero_and_one():
    v = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    b = atmosh.prt.bake(v, [[0, 1, 2]], bands=2, mode="unshadowed")  # one triangle
    assert b["transfer"].shape == (3, 4)
    light = atmosh.prt.directional_light(2, [0.0, 0.0, 1.0])
    assert atmosh.prt.relight(np.zeros((0, 4)), light).shape == (0,)
    assert atmosh.prt.relight(b["transfer"][:1], light).shape == (1,)
    assert atmosh.prt.unshadowed_transfer(2, np.zeros((0, 3)), 0.5).shape == (0, 4)


def test_bad_input():
    v = np.zeros((3, 3))
    with pytest.raises(atmosh.InputError, match="vertex index 5"):
        atmosh.prt.bake(v, [[0, 1, 5]])
    with pytest.raises(atmosh.InputError, match="shape"):
        atmosh.prt.bake(np.zeros((3, 2)), [[0, 1, 2]])
    with pytest.raises(atmosh.InputError, match="mode|lit"):
        v = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
        atmosh.prt.bake(v, [[0, 1, 2]], mode="lit")
    with pytest.raises(atmosh.InputError):
        atmosh.prt.builtin_scene("teapot")
