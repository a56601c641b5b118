#!/usr/bin/env python3
"""Reference accelerations of the EGM2008 file in this directory, from an independent code.

Usage: gravity_oracle.py > gravity_oracle.csv   (run from nav-sim/data/)

pyshtools 4.14.1 (SHTOOLS, Wieczorek & Meschede 2018; `pip install pyshtools==4.14.1`) reads
EGM2008_60.gfc with its own ICGEM reader and evaluates the gradient of the potential with its
own Legendre functions (pyshtools.gravmag.MakeGravGridPoint, 4-pi normalised, no
Condon-Shortley phase: the geodesy convention of ICGEM files). Its (r, theta, phi) components
are turned into Earth-fixed Cartesian ones here. nav-sim's test
(nav-sim/tests/testsuite/gravity_field.rs) compares its own evaluation with every row.

Columns: degree, order (largest kept; higher orders zeroed), x_m, y_m, z_m (Earth-fixed), then
the complete field g (m/s^2) and the remainder without C00 and C20 (what nav-sim adds to point
mass + J2), both Earth-fixed Cartesian.
"""

import math

import numpy as np
import pyshtools

POINTS_M = [
    # (radius, geocentric latitude, longitude): surface, LEO (200, 500 km), near a pole, MEO.
    (6378137.0, 0.0, 0.0),
    (6578137.0, 40.958, 100.291),
    (6878137.0, -33.3, 251.7),
    (6878137.0, 89.2, 17.0),
    (6878137.0, -88.7, 200.5),
    (8378137.0, 12.5, -75.25),
]
TRUNCATIONS = [(2, 0), (20, 20), (20, 10), (60, 60)]


def cartesian(vector_rtp, colatitude, longitude):
    """(r, theta, phi) components to Cartesian ones."""
    st, ct = math.sin(colatitude), math.cos(colatitude)
    sp, cp = math.sin(longitude), math.cos(longitude)
    e_r = np.array([st * cp, st * sp, ct])
    e_theta = np.array([ct * cp, ct * sp, -st])
    e_phi = np.array([-sp, cp, 0.0])
    return vector_rtp[0] * e_r + vector_rtp[1] * e_theta + vector_rtp[2] * e_phi


def acceleration(cilm, gm, r0, radius, latitude_deg, longitude_deg, degree):
    rtp = pyshtools.gravmag.MakeGravGridPoint(
        cilm, gm, r0, radius, latitude_deg, longitude_deg, lmax=degree
    )
    return cartesian(rtp, math.radians(90.0 - latitude_deg), math.radians(longitude_deg))


def main():
    cilm_full, gm, r0 = pyshtools.shio.read_icgem_gfc("EGM2008_60.gfc", lmax=60)
    print("degree,order,x_m,y_m,z_m,g_x,g_y,g_z,remainder_x,remainder_y,remainder_z")
    for degree, order in TRUNCATIONS:
        cilm = np.array(cilm_full[:, : degree + 1, : degree + 1])
        cilm[:, :, order + 1 :] = 0.0
        remainder = cilm.copy()
        remainder[0, 0, 0] = 0.0
        remainder[0, 2, 0] = 0.0
        for radius, latitude, longitude in POINTS_M:
            lat, lon = math.radians(latitude), math.radians(longitude)
            position = radius * np.array(
                [math.cos(lat) * math.cos(lon), math.cos(lat) * math.sin(lon), math.sin(lat)]
            )
            full = acceleration(cilm, gm, r0, radius, latitude, longitude, degree)
            rest = acceleration(remainder, gm, r0, radius, latitude, longitude, degree)
            values = [*position, *full, *rest]
            print(f"{degree},{order}," + ",".join(repr(float(v)) for v in values))


if __name__ == "__main__":
    main()
