"""aperture.solar_position: the engine's NOAA sun position."""

import datetime

import pytest

import aperture


def test_against_the_nrel_spa_reference_case():
    # Reda & Andreas 2004 (NREL SPA), the example of its Table A4.1: 2003-10-17 12:30:30
    # at UTC-7, 39.742476 N, 105.1786 W; topocentric azimuth 194.34024 deg, zenith angle
    # 50.11162 deg with refraction. NOAA's algorithm is good to about 0.02 deg
    # (terrain/light/solar_position.h); the difference in parallax is 0.002 deg.
    azimuth, elevation = aperture.solar_position("2003-10-17T12:30:30-07:00", 39.742476,
                                                 -105.1786)
    assert azimuth == pytest.approx(194.34024, abs=0.05)
    assert elevation == pytest.approx(90 - 50.11162, abs=0.05)


def test_every_way_of_giving_the_instant_agrees():
    utc = datetime.datetime(2024, 6, 21, 17, 45, 30)
    expected = aperture.solar_position("2024-06-21T17:45:30Z", 36.6, -84.2)
    assert aperture.solar_position(utc, 36.6, -84.2) == expected  # naive: UTC
    eastern = datetime.timezone(datetime.timedelta(hours=-4))
    assert aperture.solar_position(utc.replace(tzinfo=datetime.timezone.utc).astimezone(eastern),
                                   36.6, -84.2) == expected
    assert aperture.solar_position("2024-06-21 13:45:30-04:00", 36.6, -84.2) == expected


def test_noon_and_night():
    # Near the June solstice at local solar noon on the tropic of Cancer the sun is
    # overhead; at midnight on the equator it is far below the horizon.
    _, elevation = aperture.solar_position("2024-06-20T12:02Z", 23.44, 0.0)
    assert elevation > 89.0
    _, night = aperture.solar_position("2024-03-20T00:00Z", 0.0, 0.0)
    assert night < -80.0
