"""The installed atmosh Python package (install component `python`) used from outside the
build tree: imports from the prefix and reproduces the SPA report's example (Reda &
Andreas 2008, NREL/TP-560-34302, Table A5.1: 2003-10-17 12:30:30 local time (-7 h),
39.742476 N, 105.1786 W, 1830.14 m, 820 mbar, 11 C, Delta T 67 s -> topocentric zenith
50.11162 deg, azimuth 194.34024 deg)."""

import os
import sys

import numpy as np

import atmosh

prefix = os.path.realpath(sys.argv[1])
where = os.path.realpath(atmosh.__file__)
if not where.startswith(prefix + os.sep):
    sys.exit(f"atmosh imported from {where}, not from the prefix {prefix}")
r = atmosh.sun.position(np.array(["2003-10-17T19:30:30"], dtype="datetime64[s]"), 39.742476, -105.1786,
                        height=1830.14, pressure=820.0, temperature=11.0, delta_t=67.0, output="dict")
zenith, azimuth = float(r["apparent_zenith_deg"][0]), float(r["azimuth_deg"][0])
if abs(zenith - 50.11162) > 5e-6 or abs(azimuth - 194.34024) > 5e-6:
    sys.exit(f"SPA example: zenith {zenith!r}, azimuth {azimuth!r} (expected 50.11162, 194.34024)")
print(f"atmosh {where}: zenith {zenith:.5f} deg, azimuth {azimuth:.5f} deg")
