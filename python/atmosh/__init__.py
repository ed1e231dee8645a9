"""atmosh: atmospheric scattering and spherical harmonics, for numpy users.

Submodules
----------
atmosh.sun   solar position (NREL SPA, Grena 2012) over numpy.datetime64 arrays
atmosh.atmo  atmospheres (presets, scene files, scene dicts), optical depth, phase functions
atmosh.sky   spectral sky radiance, sky images, XYZ / sRGB / luminance
atmosh.sh    real spherical harmonics: projection, evaluation, rotation, convolution
atmosh.prt   precomputed radiance transfer on meshes given as arrays
atmosh.io    the EXR files atmosh writes, read into numpy
atmosh.studies  the studies as pandas.DataFrame (sky images as xarray.Dataset)

Units are SI unless a name says otherwise (angles in degrees where the name ends in
_deg, wavelengths in nm). Bad input raises atmosh.InputError (a ValueError) with the
one-line message of the C++ library (the same text the atmosh command line prints).
docs/python.md has the whole API.
"""

from ._atmosh import InputError  # noqa: F401
from . import sun, atmo, sky, sh, prt, io, studies  # noqa: F401

__all__ = ["InputError", "sun", "atmo", "sky", "sh", "prt", "io", "studies"]
