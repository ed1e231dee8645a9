"""Real spherical harmonics on arrays (atmosh/sh/*.hpp), same conventions as the C++ API.

Basis: orthonormal real SH with the Condon-Shortley phase; coefficient index
i = l (l + 1) + m (l < L bands, |m| <= l), L^2 coefficients. Coefficient arrays are
(L^2,) for one channel or (C, L^2) for C channels. Directions are unit vectors
(x, y, z) with theta from +z and phi from +x towards +y. Coefficients carry the units
of the function times sr^(1/2) (integral f Y dOmega).

Images: equirect (H, W, C) arrays, row 0 at theta = 0 (+z), column 0 at phi = 0, pixel
centre (col + 1/2, row + 1/2) at phi = 2 pi (col + 1/2) / W, theta = pi (row + 1/2) / H.
Cube maps: (6, N, N, C) arrays, faces +X, -X, +Y, -Y, +Z, -Z with the OpenGL
orientation (cube_directions(N) gives each texel's direction).
"""

import numpy as np

from . import _atmosh

_sh = _atmosh.sh

__all__ = ["evaluate", "reconstruct", "grid", "analyse", "synthesise", "project_equirect", "project_cube",
           "cube_directions", "render_equirect", "rotate", "irradiance_factors", "convolve", "irradiance",
           "irradiance_at", "band_energy", "window", "apply_window", "convert", "bands_of"]


def _as2d(coeffs):
    c = np.asarray(coeffs, dtype=np.float64)
    if c.ndim == 1:
        return np.ascontiguousarray(c[np.newaxis, :]), True
    if c.ndim != 2:
        raise _atmosh.InputError("coefficients: expected shape (L^2,) or (C, L^2), got shape %s" % (c.shape,))
    return np.ascontiguousarray(c), False


def _back(c, single):
    return c[0] if single else c


def bands_of(coeffs):
    """Band count L of a coefficient array (last axis L^2)."""
    n = np.asarray(coeffs).shape[-1]
    L = int(round(np.sqrt(n)))
    if L * L != n or n < 1:
        raise _atmosh.InputError("coefficients: last axis has %d values, not a square L^2 >= 1" % n)
    return L


def evaluate(bands, directions):
    """Y_i(d) for unit directions (..., 3): shape (..., L^2). InputError for non-unit directions."""
    d = np.asarray(directions, dtype=np.float64)
    out = _sh.evaluate(bands, np.ascontiguousarray(d.reshape(-1, 3)))
    return out.reshape(d.shape[:-1] + (out.shape[-1],))


def reconstruct(coeffs, directions):
    """f(d) = sum_i c_i Y_i(d): shape (...) for (L^2,) coefficients, (..., C) for (C, L^2)."""
    c = np.asarray(coeffs, dtype=np.float64)
    y = evaluate(bands_of(c), directions)
    return y @ c if c.ndim == 1 else y @ c.T


def grid(bands, rule="gauss", nlat=0, nphi=0):
    """A quadrature grid for analyse/synthesise: dict cos_theta (nlat,) descending from +z,
    sin_theta, weights (latitude weights, sum 2), phi (nphi,) [rad] and directions
    (nlat, nphi, 3). rule: "gauss" (exact for L bands with nlat >= L, nphi >= 2L - 1),
    "fejer" (equiangular ring centres), "clenshaw-curtis" (rings with both poles).
    nlat, nphi = 0: the smallest exact size."""
    g = _sh.grid(bands, rule, nlat, nphi)
    ct, st, ph = g["cos_theta"], g["sin_theta"], g["phi"]
    g["directions"] = np.stack([st[:, None] * np.cos(ph)[None, :], st[:, None] * np.sin(ph)[None, :],
                                np.broadcast_to(ct[:, None], (len(ct), len(ph)))], axis=-1)
    return g


def analyse(values, bands, rule="gauss", threads=1, fft="estimate"):
    """SH coefficients of samples on a grid(bands, rule, nlat, nphi): values (nlat, nphi)
    -> (L^2,), or (C, nlat, nphi) -> (C, L^2). Exact for band-limited functions on a
    Gauss grid. fft: "estimate" (FFT plans from nphi alone: the same bits in every run) or
    "measure" (FFTW's plans chosen by timing at the first call of each nphi, 0.2-1 s once:
    faster for some nphi other than powers of two, e.g. ~12 % at 768; the last bits may
    differ between runs)."""
    v = np.asarray(values, dtype=np.float64)
    single = v.ndim == 2
    out = _sh.analyse(np.ascontiguousarray(v[np.newaxis] if single else v), bands, rule, threads, fft)
    return _back(out, single)


def synthesise(coeffs, rule="gauss", nlat=0, nphi=0, threads=1, fft="estimate"):
    """Values of coefficients on a grid: (nlat, nphi), or (C, nlat, nphi) for (C, L^2).
    fft as for analyse."""
    c, single = _as2d(coeffs)
    return _back(_sh.synthesise(c, rule, nlat, nphi, threads, fft), single)


def project_equirect(image, bands, rule="exact", threads=1):
    """SH coefficients of an equirect image (H, W) or (H, W, C): (L^2,) or (C, L^2).

    rule: "exact" (exact for band-limited content; ring weights of a quadrature),
    "solid-angle" (pixel solid angles), "pixel-integrated" (basis integrated over pixels).
    """
    im = np.asarray(image, dtype=np.float64)
    single = im.ndim == 2
    out = _sh.project_equirect(np.ascontiguousarray(im[..., np.newaxis] if single else im), bands, rule, threads)
    return _back(out, single)


def project_cube(faces, bands, threads=1):
    """SH coefficients of a cube map (6, N, N) or (6, N, N, C) (exact texel solid angles):
    (L^2,) or (C, L^2)."""
    f = np.asarray(faces, dtype=np.float64)
    single = f.ndim == 3
    out = _sh.project_cube(np.ascontiguousarray(f[..., np.newaxis] if single else f), bands, threads)
    return _back(out, single)


def cube_directions(size):
    """Unit direction of every texel centre of a cube map: (6, size, size, 3)."""
    return _sh.cube_directions(size)


def render_equirect(coeffs, width, height):
    """Reconstruction at equirect pixel centres: (H, W) or (H, W, C) (float32 precision)."""
    c, single = _as2d(coeffs)
    out = _sh.render_equirect(c, width, height)
    return out[..., 0] if single else out


def rotate(coeffs, matrix=None, euler_zyz=None):
    """Actively rotated coefficients: f'(r) = f(R^-1 r) (a lobe along d then points along R d).

    matrix     (3, 3) proper rotation acting on column vectors, or
    euler_zyz  (alpha, beta, gamma) [rad]: R = Rz(alpha) Ry(beta) Rz(gamma).
    """
    c, single = _as2d(coeffs)
    if (matrix is None) == (euler_zyz is None):
        raise _atmosh.InputError("rotate: give exactly one of matrix or euler_zyz")
    if matrix is not None:
        out = _sh.rotate_matrix(c, np.asarray(matrix, dtype=np.float64))
    else:
        a, b, g = (float(x) for x in euler_zyz)
        out = _sh.rotate_euler(c, a, b, g)
    return _back(out, single)


def irradiance_factors(bands):
    """Clamped-cosine factors A_l = pi, 2 pi/3, pi/4, 0, -pi/24, ... (Ramamoorthi & Hanrahan 2001)."""
    return np.asarray(_sh.irradiance_factors(bands))


def convolve(coeffs, factors):
    """Zonal convolution c'_lm = factors[l] c_lm (Funk-Hecke factors, one per band)."""
    c, single = _as2d(coeffs)
    return _back(_sh.convolve(c, [float(x) for x in factors]), single)


def irradiance(radiance_coeffs):
    """Irradiance coefficients E (W m^-2 for radiance in W m^-2 sr^-1) of radiance coefficients."""
    return convolve(radiance_coeffs, irradiance_factors(bands_of(radiance_coeffs)))


def irradiance_at(radiance_coeffs, normals):
    """Irradiance E(n) = int max(0, n.w) L(w) dw at unit normals (N, 3): (N,) or (N, C)."""
    c, single = _as2d(radiance_coeffs)
    n = np.asarray(normals, dtype=np.float64)
    out = _sh.irradiance_at(c, np.ascontiguousarray(n.reshape(-1, 3)))
    out = out[:, 0] if single else out
    return out.reshape(n.shape[:-1] + out.shape[1:])


def band_energy(coeffs):
    """Energy per band e_l = sum_m c_lm^2 (rotation invariant): (L,) or (C, L)."""
    c, single = _as2d(coeffs)
    return _back(_sh.band_energy(c), single)


def window(name, bands):
    """Window weights w_l (L,) against ringing: "none", "hanning", "lanczos" (Sloan 2008),
    "nonnegative" (smallest Gaussian making the windowed delta >= 0)."""
    return np.asarray(_sh.window_weights(name, bands))


def apply_window(coeffs, name):
    """Coefficients with band l multiplied by window(name, L)[l]."""
    return convolve(coeffs, window(name, bands_of(coeffs)))


def convert(coeffs, from_normalization="orthonormal", to_normalization="orthonormal", from_condon_shortley=True,
            to_condon_shortley=True):
    """The same function's coefficients in another normalisation ("orthonormal", "4pi",
    "schmidt") and Condon-Shortley convention."""
    c, single = _as2d(coeffs)
    return _back(_sh.convert(c, from_normalization, from_condon_shortley, to_normalization, to_condon_shortley),
                 single)
