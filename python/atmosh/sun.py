"""Solar position over arrays of instants (atmosh/atmo/sun_position.hpp)."""

import numpy as np

from . import _atmosh

_sun = _atmosh.sun

__all__ = ["position", "julian_day"]

_UNIX_EPOCH_JD = 2440587.5  # JD of 1970-01-01T00:00:00 UTC


def julian_day(times):
    """UTC Julian days [days] of `times`, as a float64 array of the same shape.

    times: numpy.datetime64 values (any unit; taken as UTC), a pandas DatetimeIndex or
    Series (tz-aware ones are converted to UTC), ISO 8601 strings (offsets such as
    "-07:00" accepted), or floats taken as Julian days already. NaT gives NaN.
    """
    try:
        import pandas as pd
    except ImportError:  # numpy inputs only
        pd = None
    if pd is not None:
        if isinstance(times, pd.Series) and isinstance(times.dtype, pd.DatetimeTZDtype):
            times = pd.DatetimeIndex(times)
        if isinstance(times, (pd.DatetimeIndex, pd.Timestamp)) and times.tz is not None:
            times = times.tz_convert("UTC").tz_localize(None)
        if isinstance(times, pd.Timestamp):
            times = times.to_datetime64()
    a = np.asarray(times)
    if a.dtype.kind in "US" or a.dtype == object and a.size and isinstance(a.flat[0], str):
        return _sun.parse_iso8601([str(s) for s in a.ravel()]).reshape(a.shape)
    if a.dtype.kind == "M":
        # microseconds: +-290 000 years, the whole SPA range (nanoseconds stop at 1677..2262)
        us = a.astype("datetime64[us]").astype(np.int64)
        nat = np.isnat(a)
        day_us = 86400 * 10**6
        days, rem = np.divmod(us, day_us)
        jd = _UNIX_EPOCH_JD + days.astype(np.float64) + rem.astype(np.float64) / day_us
        return np.where(nat, np.nan, jd)
    if a.dtype.kind in "fiu":
        return a.astype(np.float64)
    raise _atmosh.InputError("times: expected numpy.datetime64 values, ISO 8601 strings or Julian days, got dtype %s"
                             % a.dtype)


def position(times, latitude, longitude, height=0.0, pressure=1013.25, temperature=15.0, delta_t=None,
             delta_ut1=0.0, algorithm="spa", output="dataframe"):
    """Topocentric sun position for every instant (vectorised; pvlib-style).

    Arguments (numpy broadcasting applies between times and every place argument):
      times       numpy.datetime64 array (UTC), pandas DatetimeIndex (tz-aware ones are
                  converted to UTC), ISO 8601 strings, or UTC Julian days (float).
      latitude    geodetic latitude [deg], WGS84, north positive, [-90, 90].
      longitude   longitude [deg], east positive, [-180, 180].
      height      height above the WGS84 ellipsoid [m] (default 0).
      pressure    air pressure for refraction [hPa] (default 1013.25).
      temperature air temperature for refraction [degC] (default 15).
      delta_t     TT - UT1 [s]; None: the Espenak & Meeus model of each instant's year.
      delta_ut1   UT1 - UTC [s], |x| <= 1 (default 0).
      algorithm   "spa" (NREL SPA, Reda & Andreas 2008, years -2000..6000, +-0.0003 deg
                  with measured Delta T) or "fast" (Grena 2012 algorithm 5, years
                  2010..2110, max 0.0027 deg against SPA); also "grena3", "grena1".
      output      "dataframe" (pandas.DataFrame indexed by the times when they are 1-D)
                  or "dict" (numpy arrays of the broadcast shape).

    Returns columns (units in the names):
      zenith_deg, elevation_deg      geometric topocentric (no refraction; drives the sky)
      apparent_zenith_deg, apparent_elevation_deg   with refraction
      azimuth_deg                    from north towards east, [0, 360)
      declination_deg, hour_angle_deg  geocentric declination, local hour angle (-180, 180]
      equation_of_time_min           [minutes]
      earth_sun_distance_au          [AU]
      delta_t_s                      the Delta T used [s]
    Same numbers as `atmosh sun --json` for the same inputs (one C++ function).
    Raises atmosh.InputError naming a bad value (e.g. a year outside the algorithm's range).
    """
    jd = julian_day(times)
    args = [jd, latitude, longitude, height, pressure, temperature, delta_ut1]
    if delta_t is not None:
        args.append(delta_t)
    b = np.broadcast_arrays(*[np.asarray(x, dtype=np.float64) for x in args])
    shape = b[0].shape
    flat = [np.ascontiguousarray(x.ravel()) for x in b]
    res = _sun.positions(flat[0], flat[1], flat[2], flat[3], flat[4], flat[5],
                         flat[7] if delta_t is not None else None, flat[6], algorithm)
    res = {k: v.reshape(shape) for k, v in res.items()}
    if output == "dict":
        return res
    if output != "dataframe":
        raise _atmosh.InputError("output: '%s' is not dataframe or dict" % output)
    import pandas as pd
    if len(shape) != 1:  # a scalar instant is one row; several axes are flattened
        res = {k: v.ravel() for k, v in res.items()}
    index = None
    t = np.asarray(times) if not hasattr(times, "tz") else times
    if getattr(t, "ndim", 0) == 1 and len(t) == len(next(iter(res.values()))):
        index = pd.Index(t, name="time")
    return pd.DataFrame(res, index=index)
