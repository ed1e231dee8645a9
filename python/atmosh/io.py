"""Files atmosh writes, read into numpy (atmosh/io/exr.hpp), and a sweep's CSV as
netCDF-CF (atmosh/io/netcdf.hpp)."""

import os

import numpy as np

from . import _atmosh

__all__ = ["read_exr", "sweep_to_netcdf"]


def read_exr(path, stack=None):
    """An OpenEXR file as written by atmosh (float32, linear, named channels).

    Returns a dict: width, height, channels {name: (H, W) float32 array, row 0 at the
    top}, attributes {name: str or float} (provenance as "atmosh:<key>", units, ...).
    stack: optional list of channel names, e.g. ["R", "G", "B"]: adds "image", the
    (H, W, len(stack)) array of those channels. InputError for an unreadable file.
    """
    d = _atmosh.io.read_exr(os.fspath(path))
    if stack is not None:
        missing = [c for c in stack if c not in d["channels"]]
        if missing:
            raise _atmosh.InputError("%s: no channel %s (has %s)" % (os.fspath(path), missing[0],
                                                                    ", ".join(d["channels"])))
        d["image"] = np.stack([d["channels"][c] for c in stack], axis=-1)
    return d


def sweep_to_netcdf(csv, netcdf, keys=None):
    """Writes a sweep's CSV (of `atmosh sweep`, or shards joined by `atmosh sweep merge`,
    e.g. after a Slurm array) as netCDF-CF, as `atmosh sweep --format netcdf` does: a grid
    of the parameter keys as coordinates, else a `point` dimension (docs/outputs.md).
    keys: the parameter keys (columns); None: those of the sweep file the CSV's `sweep`
    provenance line names. InputError for a key that is not a column."""
    _atmosh.io.sweep_to_netcdf(os.fspath(csv), os.fspath(netcdf), None if keys is None else [str(k) for k in keys])
