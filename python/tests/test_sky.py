"""atmosh.sky against `atmosh sky --json` (the same integrator), the image projection
conventions and colour closed forms."""

import math

import numpy as np
import pytest

import atmosh
from conftest import cli_message


@pytest.fixture(scope="module")
def sky():
    # The default scene with single scattering: `atmosh sky --scattering single`.
    return atmosh.sky.Sky(scattering="single")


def _summary(sky, sun):
    wl = sky.wavelengths_nm
    views = atmosh.sky.directions([90.0, 1.0, 1.0], [0.0, sun[1], (sun[1] + 180.0) % 360.0])
    xyz = atmosh.sky.to_xyz(sky.radiance(views, sun), wl)
    return xyz, atmosh.sky.xyz_to_srgb(xyz)


def test_radiance_and_irradiance_match_cli(cli, sky, tmp_path):
    j = cli.json("sky", "--sun-elevation", 30, "--sun-azimuth", 135, "--scattering", "single", "--size", "8x4",
                 "-o", tmp_path / "sky.exr")
    assert sky.scattering_method == j["scattering"] == "single"
    np.testing.assert_array_equal(sky.wavelengths_nm, j["wavelengths_nm"])
    xyz, srgb = _summary(sky, (30.0, 135.0))
    assert xyz[0, 1] == pytest.approx(j["zenith_luminance_cd_m2"], rel=1e-12)
    assert xyz[1, 1] == pytest.approx(j["horizon_luminance_cd_m2"], rel=1e-12)
    np.testing.assert_allclose(srgb[1], j["horizon_srgb"], rtol=1e-12)
    np.testing.assert_allclose(srgb[2], j["horizon_away_srgb"], rtol=1e-12)
    irr = sky.irradiance((30.0, 135.0))
    np.testing.assert_allclose(irr["diffuse_w_m2_nm"], j["irradiance_diffuse_w_m2_nm"], rtol=1e-12)
    np.testing.assert_allclose(irr["direct_w_m2_nm"], j["irradiance_direct_w_m2_nm"], rtol=1e-12)
    assert irr["diffuse_lux"] == pytest.approx(j["irradiance_diffuse_lux"], rel=1e-12)


@pytest.mark.parametrize("projection", ["equirect", "fisheye"])
def test_image_equals_the_cli_exr(cli, sky, tmp_path, projection):
    f = tmp_path / "sky.exr"
    cli.text("sky", "--sun-elevation", 12, "--sun-azimuth", 250, "--scattering", "single", "--size", "24x12",
             "--projection", projection, "--spectral", "-o", f)
    exr = atmosh.io.read_exr(f, stack=["X", "Y", "Z"])
    img = sky.image((12.0, 250.0), 24, 12, projection=projection, spectral=True)
    assert exr["width"] == 24 and exr["height"] == 12
    np.testing.assert_array_equal(img["xyz"], exr["image"])  # the same float32 render
    rgb = np.stack([exr["channels"][c] for c in "RGB"], axis=-1)
    np.testing.assert_array_equal(img["srgb"], rgb)
    for i, wl in enumerate(img["wavelengths_nm"]):
        name = [c for c in exr["channels"] if c.startswith("L_") and abs(float(c[2:-2]) - wl) < 0.01]
        assert len(name) == 1, wl
        np.testing.assert_array_equal(img["spectral"][..., i], exr["channels"][name[0]])


def test_scene_file_with_observer_matches_cli(cli, tmp_path):
    scene = {
        "name": "python-test",
        "planet": {"radius_m": 6360e3, "atmosphere_top_m": 60e3},
        "rayleigh": {"model": "coefficients", "scattering_per_m": 13.558e-6, "reference_nm": 550.0,
                     "profile": {"model": "exponential", "scale_height_m": 8000.0}},
        "mie": {"scattering_per_m": 4e-6, "profile": {"model": "exponential", "scale_height_m": 1200.0},
                "phase": {"model": "hg", "g": 0.7}},
        "spectrum": {"from_nm": 400.0, "to_nm": 700.0, "count": 8},
        "scattering": {"method": "single"},
        "observer": {"latitude_deg": 48.8566, "longitude_deg": 2.3522, "height_m": 35.0,
                     "time_utc": "2026-06-21T15:30:00Z"},
    }
    a = atmosh.atmo.atmosphere(scene)
    f = tmp_path / "scene.toml"
    f.write_text(a.to_toml())
    j = cli.json("sky", "--scene", f, "--size", "8x4", "-o", tmp_path / "sky.exr")
    sun = a.scene_sun()
    assert sun["elevation_deg"] == pytest.approx(j["sun_elevation_deg"], abs=1e-12)
    assert sun["apparent_elevation_deg"] == pytest.approx(j["apparent_sun_elevation_deg"], abs=1e-12)
    sky = atmosh.sky.Sky(a, sun_distance_au=sun["earth_sun_distance_au"])
    # The CLI places the observer at the scene's height (35 m) above the ground.
    zen = sky.radiance([[0.0, 0.0, 1.0]], (sun["elevation_deg"], sun["azimuth_deg"]), altitude_m=35.0)
    assert atmosh.sky.luminance(zen, sky.wavelengths_nm)[0] == pytest.approx(j["zenith_luminance_cd_m2"], rel=1e-12)


def test_image_pixels_are_the_radiance_of_their_directions(sky):
    W, H = 16, 8
    img = sky.image((20.0, 90.0), W, H, sun_disc=False, spectral=True)
    assert img["xyz"].shape == (H, W, 3) and img["spectral"].shape == (H, W, len(sky.wavelengths_nm))
    assert img["valid"].all()
    # Equirect: azimuth (x + 0.5) / W * 360 from north towards east, elevation 90 - (y + 0.5) / H * 180.
    az = (np.arange(W) + 0.5) / W * 360.0
    el = 90.0 - (np.arange(H) + 0.5) / H * 180.0
    views = atmosh.sky.directions(el[:, None], az[None, :])
    L = sky.radiance(views, (20.0, 90.0))
    assert L.shape == (H, W, len(sky.wavelengths_nm))
    np.testing.assert_allclose(img["spectral"], L, rtol=2e-6, atol=1e-30)
    np.testing.assert_allclose(img["xyz"], atmosh.sky.to_xyz(L, sky.wavelengths_nm), rtol=2e-6, atol=1e-30)
    fish = sky.image((20.0, 90.0), 8, 8, projection="fisheye")
    assert not fish["valid"][0, 0] and fish["valid"][4, 4]
    assert fish["xyz"][0, 0, 1] == 0.0


def test_shapes_zero_and_one(sky):
    nw = len(sky.wavelengths_nm)
    assert sky.radiance(np.zeros((0, 3)), (30.0, 180.0)).shape == (0, nw)
    assert sky.radiance([[0.0, 0.0, 1.0]], (30.0, 180.0)).shape == (1, nw)
    assert atmosh.sky.to_xyz(np.zeros((0, nw)), sky.wavelengths_nm).shape == (0, 3)
    assert atmosh.sky.directions([], []).shape == (0, 3)


def test_colour_closed_forms():
    # sRGB transfer function (IEC 61966-2-1): 12.92 v below 0.0031308, 1.055 v^(1/2.4) - 0.055 above.
    v = np.array([0.0, 0.002, 0.0031308, 0.5, 1.0])
    ref = np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)
    np.testing.assert_allclose(atmosh.sky.srgb_encode(v), ref, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(atmosh.sky.srgb_decode(atmosh.sky.srgb_encode(v)), v, rtol=1e-12, atol=1e-15)
    # D65 white (x, y) = (0.3127, 0.3290) with Y = 1 is R = G = B = 1.
    x, y = 0.3127, 0.3290
    white = np.array([x / y, 1.0, (1 - x - y) / y])
    np.testing.assert_allclose(atmosh.sky.xyz_to_srgb(white), [1.0, 1.0, 1.0], rtol=1e-12)
    np.testing.assert_allclose(atmosh.sky.srgb_to_xyz(atmosh.sky.xyz_to_srgb(white)), white, rtol=1e-12)
    xy = atmosh.sky.xy_chromaticity(np.array([[0.0, 0.0, 0.0], white]))
    assert np.isnan(xy[0]).all()
    np.testing.assert_allclose(xy[1], [x, y], rtol=1e-12)
    # A flat spectrum of 1 W m^-2 sr^-1 nm^-1 has Y = 683 * (integral of ybar) = 683 * 106.857 (CIE 1931,
    # 1 nm sum over 360-830 nm) when held constant across the table.
    wl = np.array([360.0, 830.0])
    assert atmosh.sky.luminance(np.ones(2), wl) == pytest.approx(683.0 * 106.857, rel=1e-4)


def test_bad_input(cli, sky, tmp_path):
    with pytest.raises(atmosh.InputError, match="unit|finite"):
        sky.radiance([[0.0, 0.0, 2.0]], (30.0, 180.0))
    with pytest.raises(atmosh.InputError, match="shape"):
        sky.radiance(np.zeros((2, 2)), (30.0, 180.0))
    code, err = cli.error("sky", "--sun-elevation", 30, "--scattering", "many", "-o", tmp_path / "x.exr")
    assert code == 2
    with pytest.raises(atmosh.InputError) as e:
        atmosh.sky.Sky("test-planet", scattering="many")
    assert str(e.value) == cli_message(err).replace("--scattering", "scattering")
    with pytest.raises(atmosh.InputError, match="projection|fisheye"):
        sky.image((30.0, 180.0), 4, 4, projection="cube")


@pytest.mark.parametrize("scattering", [
    {"method": "approximate", "ms_altitudes": 4, "ms_sun_directions": 8, "ms_zenith_directions": 4,
     "ms_azimuth_directions": 2, "ms_ray_steps": 8},
    {"method": "orders", "orders": 2, "orders_radii": 4, "orders_view_directions": 8, "orders_sun_directions": 4,
     "orders_azimuths": 4, "orders_sphere_zenith": 4, "orders_sphere_azimuth": 4, "orders_ray_steps": 4},
])
def test_the_scenes_scattering_method_matches_cli(cli, tmp_path, scattering):
    import tomllib
    scene = tomllib.loads(atmosh.atmo.atmosphere("test-planet").to_toml())
    scene["scattering"] = scattering  # small tables: the same code path, milliseconds to build
    scene["sun"] = {"elevation_deg": 20.0, "azimuth_deg": 100.0}
    a = atmosh.atmo.atmosphere(scene)
    f = tmp_path / "scene.toml"
    f.write_text(a.to_toml())
    j = cli.json("sky", "--scene", f, "--size", "8x4", "-o", tmp_path / "sky.exr")
    sky = atmosh.sky.Sky(a)
    assert sky.scattering_method == j["scattering"] == scattering["method"]
    xyz, srgb = _summary(sky, (20.0, 100.0))
    assert xyz[0, 1] == pytest.approx(j["zenith_luminance_cd_m2"], rel=1e-12)
    np.testing.assert_allclose(srgb[1], j["horizon_srgb"], rtol=1e-12)
    single = atmosh.sky.Sky(a, scattering="single")
    assert _summary(single, (20.0, 100.0))[0][0, 1] < xyz[0, 1]  # more light with the higher orders
