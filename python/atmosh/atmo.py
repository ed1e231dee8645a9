"""Atmospheres, optical depth along arrays of rays, phase functions on arrays
(atmosh/atmo/atmosphere.hpp, optical_depth.hpp, phase.hpp; scene schema in
docs/scene-format.md)."""

import os

import numpy as np

from . import _atmosh, _toml

_atmo = _atmosh.atmo

__all__ = ["Atmosphere", "atmosphere", "preset_names", "PhaseFunction", "phase"]


def preset_names():
    """Names of the built-in atmospheres ("earth-physical", "earth-graphics", "test-planet")."""
    return list(_atmo.preset_names())


class Atmosphere:
    """An atmosphere ready for computation, with the scene it came from.

    Build it with atmosh.atmo.atmosphere(source). Attributes: name, source,
    wavelengths_nm (its spectral grid [nm]), ground_radius_m, top_radius_m,
    ground_albedo, constituents (subset of "rayleigh", "mie", "ozone"),
    scattering_method ("single", "orders", "approximate": the scene's [scattering]),
    scattering_orders, sun_model ("disc" or "point").
    """

    def __init__(self, native):
        self._native = native

    def __getattr__(self, name):
        if name in ("name", "source", "ground_radius_m", "top_radius_m", "ground_albedo", "constituents",
                    "scattering_method", "scattering_orders", "sun_model"):
            return getattr(self._native, name)
        raise AttributeError(name)

    @property
    def wavelengths_nm(self):
        return self._native.wavelengths_nm

    def __repr__(self):
        return "<atmosh.atmo.Atmosphere %r from %s, %d wavelengths, %s>" % (
            self.name, self.source, len(self.wavelengths_nm), "+".join(self.constituents))

    def to_toml(self):
        """The scene as TOML text (docs/scene-format.md); reads back equal."""
        return self._native.to_toml()

    def scene_sun(self):
        """The scene's sun as a dict (elevation_deg, azimuth_deg, earth_sun_distance_au,
        observer_height_m; apparent_elevation_deg with an [observer]), from NREL SPA at the
        [observer]'s place and time, or the [sun] table; None when the scene places no sun."""
        return self._native.scene_sun()

    def extinction(self):
        """Extinction coefficients [1/m] at relative density 1, shape (wavelengths, 3):
        columns rayleigh, mie, ozone (0 for an absent constituent)."""
        return self._native.extinction()

    def scattering(self):
        """Scattering coefficients [1/m] at relative density 1, shape (wavelengths, 3)."""
        return self._native.scattering()

    def density(self, altitude_m):
        """Relative densities (rayleigh, mie, ozone) at altitudes [m] above the ground: shape (N, 3)."""
        a = np.asarray(altitude_m, dtype=np.float64)
        return self._native.density(np.ascontiguousarray(a.ravel())).reshape(a.shape + (3,))

    def columns(self, altitude_m, cos_zenith, length_m=None, method="reference", shells=40, directions=64):
        """Column X_c = integral of relative density along straight rays [m], per constituent.

        altitude_m  ray origins above the ground [m] (>= 0), broadcast with cos_zenith.
        cos_zenith  cosine of the ray's zenith angle at its origin (1 up, 0 horizontal,
                    < 0 down; a ray that meets the ground stops there).
        length_m    optional ray lengths [m] (method "reference" only; default: to the
                    top of the atmosphere or the ground).
        method      "reference" (adaptive Gauss-Kronrod, ~1e-12 relative) or "lut"
                    (Nishita tables, `shells` x `directions`; ~1e-5..6e-4 relative).
        Returns a dict: column_m (..., 3), error_m (..., 3) (estimated, reference only;
        NaN for lut), hits_ground (...) bool.
        """
        b = [np.asarray(x, dtype=np.float64) for x in (altitude_m, cos_zenith)]
        if length_m is not None:
            b.append(np.asarray(length_m, dtype=np.float64))
        b = np.broadcast_arrays(*b)
        shape = b[0].shape
        flat = [np.ascontiguousarray(x.ravel()) for x in b]
        col, err, hits = self._native.columns(flat[0], flat[1], flat[2] if length_m is not None else None,
                                              method, shells, directions)
        return {"column_m": col.reshape(shape + (3,)), "error_m": err.reshape(shape + (3,)),
                "hits_ground": hits.reshape(shape)}

    def optical_depth(self, altitude_m, cos_zenith, length_m=None, method="reference", by_constituent=False,
                      shells=40, directions=64):
        """Optical depth tau(lambda) = sum_c extinction_c(lambda) X_c along rays (dimensionless).

        Arguments as columns(). Returns shape (..., wavelengths), or with by_constituent
        (..., wavelengths, 3) (rayleigh, mie, ozone). The same sum as
        `atmosh atmo optical-depth --json` for the same ray and wavelength.
        """
        x = self.columns(altitude_m, cos_zenith, length_m, method, shells, directions)["column_m"]
        tau = x[..., np.newaxis, :] * self.extinction()
        if by_constituent:
            return tau
        return (tau[..., 0] + tau[..., 1]) + tau[..., 2]

    def transmittance(self, altitude_m, cos_zenith, length_m=None, method="reference", shells=40, directions=64):
        """Direct transmittance exp(-tau) along rays, shape (..., wavelengths); exactly 0
        (never NaN) for infinite optical depth."""
        return np.exp(-self.optical_depth(altitude_m, cos_zenith, length_m, method, False, shells, directions))


def atmosphere(source=None, wavelengths_nm=None):
    """An Atmosphere from a preset, a scene file, scene TOML text or a scene dict.

    source:
      None               the built-in default scene (the one `atmosh sky` uses)
      a preset name      one of preset_names(); single scattering, disc sun
      a path             a scene TOML file (str or os.PathLike; docs/scene-format.md)
      a dict             a scene with the file's schema, e.g.
                         {"planet": {"radius_m": 6360e3, "atmosphere_top_m": 60e3},
                          "rayleigh": {...}, "spectrum": {"wavelengths_nm": [450, 550, 650]}}
                         (written as TOML and read by the same strict parser;
                         "version" defaults to 1)
    wavelengths_nm: optional wavelengths [nm] replacing the source's spectrum.
    Raises atmosh.InputError naming the bad key or value (the message of `atmosh scene check`).
    """
    wl = None if wavelengths_nm is None else [float(w) for w in np.atleast_1d(wavelengths_nm)]
    if source is None:
        return Atmosphere(_atmo.Atmosphere.default_scene(wl))
    if isinstance(source, dict):
        if "version" not in source:
            source = {"version": 1, **source}
        return Atmosphere(_atmo.Atmosphere.from_toml(_toml.dumps(source), "<dict>", wl))
    if isinstance(source, os.PathLike):
        return Atmosphere(_atmo.Atmosphere.from_file(os.fspath(source), wl))
    if isinstance(source, str):
        if source in preset_names():
            return Atmosphere(_atmo.Atmosphere.from_preset(source, wl))
        if source.endswith(".toml") or os.path.exists(source):
            return Atmosphere(_atmo.Atmosphere.from_file(source, wl))
        return Atmosphere(_atmo.Atmosphere.from_preset(source, wl))  # InputError listing the presets
    raise _atmosh.InputError("atmosphere: expected a preset name, a scene file or a scene dict, got %s"
                             % type(source).__name__)


class PhaseFunction:
    """A scattering phase function [1/sr], normalised so 2 pi int p(mu) dmu = 1.

    model: "rayleigh" (depolarization), "hg" (g), "cornette-shanks" (g), "double-hg"
    (g, g2, weight), "tabulated" (cos_theta, value: piecewise linear, normalised).
    |g| < 1. InputError for bad parameters.
    """

    def __init__(self, model, g=None, g2=-0.3, weight=0.9, depolarization=0.0279, cos_theta=None, value=None):
        if model in ("hg", "cornette-shanks", "double-hg") and g is None:
            raise _atmosh.InputError("g: required for model %s" % model)
        self._native = _atmo.PhaseFunction(model, 0.0 if g is None else float(g), g2, weight, depolarization,
                                           None if cos_theta is None else list(np.asarray(cos_theta, float)),
                                           None if value is None else list(np.asarray(value, float)))

    def __call__(self, cos_theta):
        """p(cos_theta) [1/sr] for an array of cosines of the scattering angle (1 = forward)."""
        return self._native.value(np.asarray(cos_theta, dtype=np.float64))

    value = __call__

    def sample(self, u):
        """Inverse-CDF map of uniform u in [0, 1] to cos_theta (density 2 pi p)."""
        return self._native.sample(np.asarray(u, dtype=np.float64))

    @property
    def mean_cosine(self):
        """<mu> = 2 pi int p mu dmu."""
        return self._native.mean_cosine

    def legendre_moments(self, n):
        """chi_l = 2 pi int p P_l dmu for l < n, and the quadrature's error estimate."""
        return self._native.legendre_moments(n)


def phase(cos_theta, model, g=None, g2=-0.3, weight=0.9, depolarization=0.0279):
    """Phase function value [1/sr] on an array of cos(theta) (see PhaseFunction)."""
    return PhaseFunction(model, g, g2, weight, depolarization)(cos_theta)
