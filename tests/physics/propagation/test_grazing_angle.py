"""One 4/3-earth grazing-angle relation for the sea-clutter patch and the two-ray specular point.

References: the law of cosines in the triangle (earth centre, antenna, surface point) evaluated
in mpmath (30 digits); the flat-earth limit arcsin(h/R); the specular-point property that both
terminals see the reflecting point at the same grazing angle (Blake 1986, ch. 6).
"""

import math

import mpmath as mp
import pytest

import diffsense  # noqa: F401
from diffsense.physics.propagation.multipath import two_ray_geometry
from diffsense.physics.propagation.refraction import horizon_distance_m, surface_grazing_angle_rad
from diffsense.sensors.radar import equation as eq


def mp_grazing(r, h, k=mp.mpf(4) / 3):
    ka = k * 6371000
    r, h = mp.mpf(r), mp.mpf(h)
    return mp.asin((2 * ka * h + h * h - r * r) / (2 * ka * r))


@pytest.mark.parametrize("r, h", [(100.0, 8.0), (5e3, 8.0), (10e3, 20.0), (2e3, 100.0), (30e3, 1000.0)])
def test_grazing_angle_law_of_cosines(r, h):
    assert float(surface_grazing_angle_rad(r, h)) == pytest.approx(float(mp_grazing(r, h)), rel=1e-12, abs=1e-16)
    # the radar chain's sea-clutter angle is the same relation
    assert float(eq.sea_grazing_angle_rad(r, h)) == float(surface_grazing_angle_rad(r, h))


def test_flat_earth_limit_and_horizon():
    assert float(surface_grazing_angle_rad(1e3, 10.0, k_factor=10.0)) == pytest.approx(
        math.asin(10 / 1e3) - 1e3 / (2 * 10 * 6371e3), rel=1e-5)
    d = float(horizon_distance_m(8.0))
    assert abs(float(surface_grazing_angle_rad(d, 8.0))) < 1e-15
    assert float(surface_grazing_angle_rad(1.1 * d, 8.0)) < 0.0  # hidden beyond the horizon


def test_two_ray_specular_point_uses_the_same_relation():
    for r, h1, h2 in ((5e3, 8.0, 3.0), (15e3, 20.0, 60.0), (2e3, 30.0, 5.0)):
        g = two_ray_geometry(r, h1, h2)
        # slant distances from each terminal to the specular point (law of cosines on the sphere)
        ka = 4 / 3 * 6371e3
        phi1, phi2 = float(g["g1"]) / ka, float(g["g2"]) / ka
        r1 = math.sqrt(h1**2 + 4 * ka * (ka + h1) * math.sin(phi1 / 2) ** 2)
        r2 = math.sqrt(h2**2 + 4 * ka * (ka + h2) * math.sin(phi2 / 2) ** 2)
        a1, a2 = float(mp_grazing(r1, h1)), float(mp_grazing(r2, h2))
        assert a1 == pytest.approx(a2, rel=1e-5)  # equal angles (Blake's cubic: small-angle solution)
        assert float(g["grazing_rad"]) == pytest.approx(0.5 * (a1 + a2), rel=1e-10)
