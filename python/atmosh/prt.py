"""Precomputed radiance transfer on meshes given as arrays (atmosh/prt/bake.hpp,
atmosh/sh/prt.hpp).

Transfer vectors use the SH basis of atmosh.sh (L^2 coefficients per vertex). Exit
radiance under distant lighting with SH coefficients l is T . l (relight).
"""

import numpy as np

from . import _atmosh

_prt = _atmosh.prt

__all__ = ["bake", "relight", "render", "builtin_scene", "builtin_scene_names", "load_mesh", "unshadowed_transfer",
           "directional_light"]


def builtin_scene_names():
    """Names of the built-in test meshes."""
    return list(_prt.builtin_scene_names())


def builtin_scene(name, resolution=32):
    """A built-in mesh: dict vertices (V, 3) [m], triangles (T, 3) int64, normals (V, 3), albedo (V,) or None."""
    return _prt.builtin_scene(name, resolution)


def load_mesh(path):
    """A mesh from an .obj or .ply file (validated; normals computed): dict as builtin_scene."""
    return _prt.load_mesh(str(path))


def bake(vertices, triangles, normals=None, albedo=None, bands=3, mode="shadowed", strata=45, seed=1, bounces=2,
         default_albedo=0.8, threads=0):
    """Per-vertex diffuse transfer by Embree ray casting (CPU).

    vertices   (V, 3) positions; triangles (T, 3) vertex indices.
    normals    (V, 3) unit normals; None: area-weighted from the triangles.
    albedo     (V,) in [0, 1]; None: default_albedo everywhere.
    bands      L (1..16); mode "unshadowed" (closed form), "shadowed" (visibility),
               "interreflected" (plus `bounces` bounces).
    strata     jittered strata per side (strata^2 sample directions), seeded by `seed`:
               the same inputs give the same transfer on any thread count.
    Returns a dict: transfer (V, L^2), ao (V,) cosine-weighted visible fraction,
    albedo (V,), normals (V, 3), bounce_energy, samples, rays, ray_seconds, mode.
    Monte Carlo error about 1e-2 of the band-0 value at 2025 samples.
    """
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles)
    if t.dtype.kind not in "iu":
        raise _atmosh.InputError("triangles: expected integer vertex indices, got dtype %s" % t.dtype)
    return _prt.bake(v, t.astype(np.int64), None if normals is None else np.asarray(normals, np.float64),
                     None if albedo is None else np.asarray(albedo, np.float64), bands, mode, strata, seed, bounces,
                     default_albedo, threads)


def relight(transfer, light):
    """Exit radiance per vertex: transfer (V, L^2) against lighting coefficients (L^2,)
    -> (V,), or (C, L^2) -> (V, C). Units: those of the light (radiance for radiance)."""
    t = np.asarray(transfer, dtype=np.float64)
    lt = np.asarray(light, dtype=np.float64)
    if t.ndim != 2 or lt.shape[-1] != t.shape[1]:
        raise _atmosh.InputError("relight: transfer (V, %s) and light %s do not match"
                                 % (t.shape[-1] if t.ndim else "?", lt.shape))
    return t @ lt if lt.ndim == 1 else t @ lt.T


def render(vertices, triangles, values, width=256, height=256, view_dir=(1.0, 0.6, 0.8)):
    """A camera image (H, W) or (H, W, C) of per-vertex values (V,) or (V, C) (e.g. relight's
    output), interpolated barycentrically on the surface seen by each pixel (Embree ray
    casting); background 0. The camera (prt::PixelCamera) looks at the bounding-box centre
    from direction view_dir (centre towards the camera), 40 deg vertical field of view, the
    bounding sphere in view; row 0 at the top."""
    val = np.asarray(values, dtype=np.float64)
    single = val.ndim == 1
    out = _prt.render_vertex_values(np.asarray(vertices, np.float64), np.asarray(triangles).astype(np.int64),
                                    np.ascontiguousarray(val[:, np.newaxis] if single else val), width, height,
                                    np.asarray(view_dir, dtype=np.float64))
    return out[..., 0] if single else out


def unshadowed_transfer(bands, normals, albedo):
    """Exact unshadowed transfer (albedo/pi) A_l Y_lm(n) for unit normals (N, 3): (N, L^2)."""
    n = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    a = np.broadcast_to(np.asarray(albedo, dtype=np.float64), (len(n),))
    return _prt.unshadowed_transfer(bands, np.ascontiguousarray(n), np.ascontiguousarray(a))


def directional_light(bands, direction, irradiance=1.0):
    """SH coefficients (L^2,) of a directional light of irradiance [W m^-2] from `direction`
    (towards the light): l_i = E Y_i(dir)."""
    return _prt.directional_light(bands, np.asarray(direction, dtype=np.float64), irradiance)
