"""atmosh.atmo against `atmosh atmo` (the same C++ library) and closed forms."""

import math

import numpy as np
import pytest

import atmosh
from conftest import cli_message


@pytest.mark.parametrize("method", ["reference", "lut"])
def test_optical_depth_matches_cli(cli, method):
    a = atmosh.atmo.atmosphere("earth-graphics", wavelengths_nm=[550.0])
    rays = ((1000.0, 60.0), (2000.0, 95.0)) if method == "reference" else ((1000.0, 60.0),)
    for altitude, zenith in rays:
        j = cli.json("optical-depth", "--preset", "earth-graphics", "--wavelength", 550, "--altitude",
                     altitude, "--zenith", zenith, "--method", method)
        mu = math.cos(math.radians(zenith))
        tau = a.optical_depth(altitude, mu, method=method, by_constituent=True)
        assert tau.shape == (1, 3)
        np.testing.assert_allclose(tau[0], [j["rayleigh"], j["mie"], j["ozone"]], rtol=1e-13, atol=0)
        total = a.optical_depth(np.array([altitude]), np.array([mu]), method=method)
        assert total.shape == (1, 1)
        assert total[0, 0] == pytest.approx(j["total"], rel=1e-13)
        assert a.transmittance(altitude, mu, method=method)[0] == pytest.approx(j["transmittance"], rel=1e-13)
        assert bool(a.columns(altitude, mu, method=method)["hits_ground"]) == j["hits_ground"]


def test_scene_dict_columns_against_the_closed_form():
    # Vertical column of exp(-h/H) from altitude h0 to the top T: H (exp(-h0/H) - exp(-T/H)).
    H, top = 8000.0, 60e3
    scene = {
        "planet": {"radius_m": 6360e3, "atmosphere_top_m": top},
        "rayleigh": {"model": "coefficients", "scattering_per_m": 13.558e-6, "reference_nm": 550.0,
                     "profile": {"model": "exponential", "scale_height_m": H}},
        "spectrum": {"wavelengths_nm": [440.0, 550.0, 680.0]},
    }
    a = atmosh.atmo.atmosphere(scene)
    assert a.constituents == ["rayleigh"]
    np.testing.assert_array_equal(a.wavelengths_nm, [440.0, 550.0, 680.0])
    h0 = np.array([0.0, 1000.0, 5000.0])
    col = a.columns(h0, 1.0)["column_m"]
    np.testing.assert_allclose(col[:, 0], H * (np.exp(-h0 / H) - math.exp(-top / H)), rtol=1e-11)
    np.testing.assert_array_equal(col[:, 1:], 0.0)
    # a vertical ray of length l from the ground: H (1 - exp(-l/H))
    part = a.columns(0.0, 1.0, length_m=[100.0, 5000.0])["column_m"][:, 0]
    np.testing.assert_allclose(part, H * (1 - np.exp(-np.array([100.0, 5000.0]) / H)), rtol=1e-11)
    # lambda^-4 scaling of the coefficients, tau = beta * X
    ext = a.extinction()[:, 0]
    np.testing.assert_allclose(ext, 13.558e-6 * (np.array([440.0, 550.0, 680.0]) / 550.0) ** -4, rtol=1e-12)
    tau = a.optical_depth(h0, 1.0)
    np.testing.assert_allclose(tau, col[:, :1] * ext[np.newaxis, :], rtol=1e-15)


def test_scene_file_and_round_trip(tmp_path):
    a = atmosh.atmo.atmosphere()  # the default scene
    f = tmp_path / "scene.toml"
    f.write_text(a.to_toml())
    b = atmosh.atmo.atmosphere(f)
    assert b.to_toml() == a.to_toml()
    np.testing.assert_array_equal(a.wavelengths_nm, b.wavelengths_nm)
    np.testing.assert_array_equal(a.extinction(), b.extinction())
    assert a.scattering_method == b.scattering_method


def test_shapes_zero_and_one():
    a = atmosh.atmo.atmosphere("test-planet", wavelengths_nm=[500.0, 600.0])
    assert a.optical_depth(np.zeros(0), np.zeros(0)).shape == (0, 2)
    assert a.columns(np.zeros(0), 1.0)["column_m"].shape == (0, 3)
    assert a.optical_depth([10.0], [0.5]).shape == (1, 2)
    assert a.optical_depth(np.zeros((2, 3)), 0.5).shape == (2, 3, 2)
    assert a.density([0.0]).shape == (1, 3)
    p = atmosh.atmo.PhaseFunction("rayleigh")
    assert p(np.zeros(0)).shape == (0,)
    assert p([0.5]).shape == (1,)


def test_phase_functions_match_cli_and_closed_forms(cli):
    mu = np.linspace(-1.0, 1.0, 9)
    g = 0.6
    hg = atmosh.atmo.phase(mu, "hg", g=g)
    np.testing.assert_allclose(hg, (1 - g * g) / (4 * math.pi * (1 + g * g - 2 * g * mu) ** 1.5), rtol=1e-14)
    # Rayleigh without depolarisation: 3/(16 pi) (1 + mu^2)
    np.testing.assert_allclose(atmosh.atmo.phase(mu, "rayleigh", depolarization=0.0),
                               3 / (16 * math.pi) * (1 + mu * mu), rtol=1e-14)
    for model, extra in (("cornette-shanks", ["--g", 0.8]),):
        j = cli.json("phase", "--model", model, "--cos-theta", 0.25, *extra)
        kw = {"g": 0.8} if extra else {}
        p = atmosh.atmo.PhaseFunction(model, **kw)
        assert p([0.25])[0] == pytest.approx(j["value"], rel=1e-15)
        assert p.mean_cosine == pytest.approx(j["mean_cosine"], rel=1e-15)
    u = np.linspace(0.0, 1.0, 5)
    s = atmosh.atmo.PhaseFunction("hg", g=0.3).sample(u)
    assert s.shape == (5,) and np.all(np.abs(s) <= 1.0)


def test_bad_input_raises_with_the_library_message(cli):
    code, err = cli.error("optical-depth", "--preset", "nope", "--wavelength", 550, "--altitude", 0,
                          "--zenith", 0)
    assert code == 2
    with pytest.raises(atmosh.InputError) as e:
        atmosh.atmo.atmosphere("nope")
    assert str(e.value) == cli_message(err)
    a = atmosh.atmo.atmosphere("test-planet", wavelengths_nm=[550.0])
    with pytest.raises(atmosh.InputError, match=r"cos_zenith\[1\] = 2"):
        a.optical_depth([0.0, 0.0], [1.0, 2.0])
    with pytest.raises(atmosh.InputError, match="altitude_m"):
        a.optical_depth(-5.0, 1.0)
    with pytest.raises(atmosh.InputError, match="scale_height_m"):
        atmosh.atmo.atmosphere({"rayleigh": {"profile": {"model": "exponential", "scale_height_m": -5.0}}})
    with pytest.raises(atmosh.InputError, match="g"):
        atmosh.atmo.PhaseFunction("hg", g=1.5)
    with pytest.raises(atmosh.InputError, match="method"):
        a.columns(0.0, 1.0, method="fast")
