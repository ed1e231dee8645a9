"""Spectral sky radiance, sky images and colour (atmosh/atmo/sky.hpp, sky_image.hpp,
colour.hpp).

Frame: the observer's East-North-Up frame (x east, y north, z up); directions point
away from the observer. Radiance: spectral radiance [W m^-2 sr^-1 nm^-1] per
wavelength of the atmosphere; XYZ with Y = luminance [cd/m^2]; linear sRGB (D65) on
the same scale. The scattering method (single, orders, approximate) is the scene's
[scattering] unless overridden.
"""

import numpy as np

from . import _atmosh
from .atmo import Atmosphere, atmosphere as _make_atmosphere

_sky = _atmosh.sky

__all__ = ["Sky", "radiance", "image", "directions", "sun_direction", "to_xyz", "luminance", "xyz_to_srgb",
           "srgb_to_xyz", "srgb_encode", "srgb_decode", "xy_chromaticity", "xyz_weights"]


def directions(elevation_deg, azimuth_deg):
    """Unit ENU directions (..., 3) from elevations [deg] above the horizon and
    azimuths [deg] from north towards east (broadcast)."""
    e, a = np.broadcast_arrays(np.asarray(elevation_deg, np.float64), np.asarray(azimuth_deg, np.float64))
    d = _sky.directions(np.ascontiguousarray(e.ravel()), np.ascontiguousarray(a.ravel()))
    return d.reshape(e.shape + (3,))


def sun_direction(elevation_deg, azimuth_deg):
    """The unit ENU direction (3,) towards a sun at a geometric elevation and azimuth [deg]."""
    return directions(float(elevation_deg), float(azimuth_deg))


def _sun_vector(sun):
    s = np.asarray(sun, dtype=np.float64)
    if s.shape == (2,):  # (elevation_deg, azimuth_deg)
        return sun_direction(s[0], s[1])
    return s


class Sky:
    """A sky integrator (Nishita single scattering plus the scene's multiple-scattering
    method) over an atmosphere; builds its optical-depth tables once.

    atmosphere     an atmosh.atmo.Atmosphere, or anything atmosh.atmo.atmosphere() takes
                   (None: the default scene, as `atmosh sky`).
    scattering     "single", "orders" or "approximate" (default: the scene's).
    orders         highest order for "orders" (default: the scene's).
    sun_model      "disc" or "point" (default: the scene's).
    shells, segments, samples, max_piece_tau: quality settings as the CLI's --shells,
                   --segments, --samples, --max-piece-tau (defaults equal).
    sun_distance_au  Earth-Sun distance [AU]; radiance scales as 1/d^2 (default 1).
    """

    def __init__(self, atmosphere=None, scattering=None, orders=None, sun_model=None, shells=32, segments=16,
                 samples=2, max_piece_tau=0.5, sun_distance_au=1.0):
        self.atmosphere = atmosphere if isinstance(atmosphere, Atmosphere) else _make_atmosphere(atmosphere)
        self._native = _sky.Sky(self.atmosphere._native, scattering, orders, sun_model, shells, segments, samples,
                                max_piece_tau, sun_distance_au)

    @property
    def wavelengths_nm(self):
        """Wavelengths [nm] of the radiance's last axis."""
        return self._native.wavelengths_nm

    @property
    def scattering_method(self):
        return self._native.scattering_method

    @property
    def sun_model(self):
        return self._native.sun_model

    def radiance(self, views, sun, altitude_m=0.0, threads=0):
        """Spectral radiance [W m^-2 sr^-1 nm^-1] along view directions.

        views       unit ENU directions, shape (N, 3) (or (..., 3)).
        sun         unit ENU direction towards the sun, shape (3,), or (elevation_deg,
                    azimuth_deg) as a pair (geometric elevation: refraction is ignored).
        altitude_m  observer altitude above the ground [m].
        threads     worker threads (0: all cores).
        Returns shape (N, wavelengths) (or (..., wavelengths)). The sun disc itself is
        not included. InputError for non-unit or non-finite directions.
        """
        v = np.asarray(views, dtype=np.float64)
        if v.ndim < 1 or v.shape[-1] != 3:
            raise _atmosh.InputError("views: expected an array of shape (N, 3), got shape %s" % (v.shape,))
        out = self._native.radiance(np.ascontiguousarray(v.reshape(-1, 3)), _sun_vector(sun), altitude_m, threads)
        return out.reshape(v.shape[:-1] + (out.shape[-1],))

    def image(self, sun, width=256, height=128, projection="equirect", altitude_m=0.0, spectral=False,
              sun_disc=True, threads=0, as_xarray=False):
        """A sky image as the CPU render gives it (`atmosh sky --device cpu`).

        projection  "equirect" (azimuth (x + 0.5)/W * 360 deg from north towards east,
                    elevation 90 - (y + 0.5)/H * 180 deg, row 0 at the zenith) or
                    "fisheye" (upper hemisphere, azimuthal equidistant, zenith at the
                    centre, north up, east to the LEFT; outside the disc masked).
        sun_disc    add the visible sun disc (the scene's sun model) as the CLI does.
        Returns a dict: xyz (H, W, 3) with Y in cd/m^2, srgb (H, W, 3) linear sRGB,
        valid (H, W) bool, wavelengths_nm, spectral (H, W, wavelengths) with spectral=True
        [W m^-2 sr^-1 nm^-1], seconds, rays. Values are float32-rounded as in the EXR.
        as_xarray   return an xarray.Dataset instead (equirect only): coordinates
                    elevation_deg, azimuth_deg (and wavelength_nm), variables X, Y, Z
                    (Y = luminance, cd/m^2), srgb_r/g/b, valid and with spectral=True
                    spectral_radiance, each with a units attribute.
        """
        img = self._native.image(_sun_vector(sun), width, height, projection, altitude_m, spectral, sun_disc, threads)
        if not as_xarray:
            return img
        if projection != "equirect":
            raise _atmosh.InputError(f"as_xarray: projection '{projection}' is not equirect")
        return _image_dataset(img, width, height, self)

    def sun_transmittance(self, sun, altitude_m=0.0):
        """Direct-beam transmittance towards the sun per wavelength (0 when the ground blocks it)."""
        return self._native.sun_transmittance(_sun_vector(sun), altitude_m)

    def irradiance(self, sun, altitude_m=0.0, zenith=24, azimuth=48):
        """Irradiance on a horizontal surface: dict with direct_w_m2_nm and diffuse_w_m2_nm
        [W m^-2 nm^-1] per wavelength and direct_lux, diffuse_lux [lx] (the numbers of
        `atmosh sky --json`: irradiance_*)."""
        return self._native.irradiance(_sun_vector(sun), altitude_m, zenith, azimuth)


def _image_dataset(img, width, height, sky):
    import xarray as xr
    el = 90.0 - (np.arange(height) + 0.5) / height * 180.0
    az = (np.arange(width) + 0.5) / width * 360.0
    dims = ("elevation_deg", "azimuth_deg")
    xyz, rgb = img["xyz"], img["srgb"]
    ds = xr.Dataset(
        {
            "X": (dims, xyz[..., 0], {"units": "cd m-2", "long_name": "CIE X (Y scale)"}),
            "Y": (dims, xyz[..., 1], {"units": "cd m-2", "long_name": "luminance (CIE Y)"}),
            "Z": (dims, xyz[..., 2], {"units": "cd m-2", "long_name": "CIE Z (Y scale)"}),
            "srgb_r": (dims, rgb[..., 0], {"units": "cd m-2", "long_name": "linear sRGB red (D65)"}),
            "srgb_g": (dims, rgb[..., 1], {"units": "cd m-2", "long_name": "linear sRGB green (D65)"}),
            "srgb_b": (dims, rgb[..., 2], {"units": "cd m-2", "long_name": "linear sRGB blue (D65)"}),
            "valid": (dims, np.asarray(img["valid"], bool)),
        },
        coords={
            "elevation_deg": ("elevation_deg", el, {"units": "degree", "long_name": "elevation above the horizon"}),
            "azimuth_deg": ("azimuth_deg", az, {"units": "degree", "long_name": "azimuth from north towards east"}),
        },
        attrs={"projection": "equirect", "scattering_method": sky.scattering_method, "sun_model": sky.sun_model,
               "seconds": float(img["seconds"])},
    )
    if "spectral" in img:
        ds = ds.assign_coords(wavelength_nm=("wavelength_nm", np.asarray(img["wavelengths_nm"], np.float64),
                                             {"units": "nm"}))
        ds["spectral_radiance"] = (dims + ("wavelength_nm",), img["spectral"], {"units": "W m-2 sr-1 nm-1"})
    return ds


def radiance(views, sun, atmosphere=None, altitude_m=0.0, scattering=None, **quality):
    """Spectral sky radiance [W m^-2 sr^-1 nm^-1] for arrays of view directions.

    views       unit ENU view directions (x east, y north, z up), shape (N, 3).
    sun         unit ENU direction towards the sun (3,), or (elevation_deg, azimuth_deg).
    atmosphere  an atmosh.atmo.Atmosphere or what atmosh.atmo.atmosphere() takes: a
                preset name, a scene file, a scene dict; None: the default scene.
    altitude_m  observer altitude above the ground [m].
    scattering  "single", "orders", "approximate"; default: the scene's [scattering].
    quality     shells, segments, samples, max_piece_tau, sun_model, orders,
                sun_distance_au (see Sky).
    Returns an array (N, wavelengths); the wavelengths [nm] are Sky(...).wavelengths_nm
    (the atmosphere's spectrum). Builds a Sky each call: keep a Sky for many calls.
    """
    return Sky(atmosphere, scattering=scattering, **quality).radiance(views, sun, altitude_m)


def image(sun, atmosphere=None, width=256, height=128, projection="equirect", **kwargs):
    """A sky image (see Sky.image) of an atmosphere (see radiance)."""
    quality = {k: kwargs.pop(k) for k in list(kwargs) if k in (
        "scattering", "orders", "sun_model", "shells", "segments", "samples", "max_piece_tau", "sun_distance_au")}
    return Sky(atmosphere, **quality).image(sun, width, height, projection, **kwargs)


def xyz_weights(wavelengths_nm):
    """Weights (wavelengths, 3) turning spectral radiance samples into XYZ (X = w[:, 0] . L):
    CIE 1931 2-degree functions against the piecewise-linear interpolant, 683 lm/W included."""
    return _sky.xyz_weights([float(w) for w in np.atleast_1d(wavelengths_nm)])


def to_xyz(spectral, wavelengths_nm):
    """CIE XYZ (..., 3) of spectral radiance (..., wavelengths) [W m^-2 sr^-1 nm^-1];
    Y is luminance [cd/m^2]."""
    return _sky.to_xyz(np.asarray(spectral, np.float64), [float(w) for w in np.atleast_1d(wavelengths_nm)])


def luminance(spectral, wavelengths_nm):
    """Luminance [cd/m^2] (...) of spectral radiance (..., wavelengths)."""
    return to_xyz(spectral, wavelengths_nm)[..., 1]


def xyz_to_srgb(xyz):
    """Linear sRGB (D65; white with Y = 1 maps to 1, 1, 1) of XYZ (..., 3), same scale."""
    return _sky.xyz_to_linear_srgb(np.asarray(xyz, np.float64))


def srgb_to_xyz(rgb):
    """XYZ (..., 3) of linear sRGB (..., 3)."""
    return _sky.linear_srgb_to_xyz(np.asarray(rgb, np.float64))


def srgb_encode(linear):
    """sRGB transfer function (IEC 61966-2-1): linear -> encoded; <= 0 and NaN -> 0, no clamp above 1."""
    return _sky.srgb_encode(np.asarray(linear, np.float64))


def srgb_decode(encoded):
    """Inverse sRGB transfer function."""
    return _sky.srgb_decode(np.asarray(encoded, np.float64))


def xy_chromaticity(xyz):
    """CIE 1931 chromaticity (..., 2) of XYZ (..., 3); NaN for black."""
    return _sky.xy_chromaticity(np.asarray(xyz, np.float64))
