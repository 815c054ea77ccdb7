"""The slit azimuth for a telescope off the dome's centre, checked on numbers worked out by hand."""

from __future__ import annotations

import pytest

from nightcrew.config import build_object
from nightcrew.errors import ConfigError
from nightcrew.modules.roof import DomeGeometry, azimuth_difference, slit_azimuth
from nightcrew.modules.sim import SimDome, SimTelescope
from nightcrew.testing import Observatory


@pytest.mark.parametrize(("alt", "az"), [(0.0, 0.0), (30.0, 123.4), (75.0, 359.5), (-5.0, 200.0)])
def test_centred_telescope_looks_along_its_own_azimuth(alt: float, az: float) -> None:
    assert slit_azimuth(DomeGeometry(radius=3.0), alt, az) == pytest.approx(az % 360.0)


@pytest.mark.parametrize(
    ("east", "north", "alt", "az", "expected"),
    [
        # Pivot 1 m east in a 2 m dome, looking north on the horizon: the axis meets the dome at
        # (1, √3), i.e. atan(1/√3) = 30° east of north.
        (1.0, 0.0, 0.0, 0.0, 30.0),
        (-1.0, 0.0, 0.0, 0.0, 330.0),
        # Pivot 1 m north, looking east: meets the dome at (√3, 1), 60° from north.
        (0.0, 1.0, 0.0, 90.0, 60.0),
        # Looking straight up from an off-centre pivot: the slit faces the pivot's side.
        (0.0, 1.0, 90.0, 0.0, 0.0),
        (1.0, 0.0, 90.0, 270.0, 90.0),
        # The offset along the line of sight changes nothing.
        (0.0, -1.0, 0.0, 180.0, 180.0),
    ],
)
def test_offset_pivot(east: float, north: float, alt: float, az: float, expected: float) -> None:
    geometry = DomeGeometry(radius=2.0, east=east, north=north)
    assert slit_azimuth(geometry, alt, az) == pytest.approx(expected, abs=1e-9)


def test_height_of_the_pivot_does_not_turn_the_slit() -> None:
    # A pivot above the centre moves the meeting point up the dome, never sideways.
    assert slit_azimuth(DomeGeometry(radius=2.0, up=1.0), 60.0, 180.0) == pytest.approx(180.0)
    assert slit_azimuth(DomeGeometry(radius=2.0, up=1.0), 10.0, 47.0) == pytest.approx(47.0)


def test_zenith_from_the_centre_keeps_the_telescope_azimuth() -> None:
    assert slit_azimuth(DomeGeometry(radius=2.0), 90.0, 211.0) == pytest.approx(211.0)


def test_offset_matters_less_at_a_bigger_dome() -> None:
    near = slit_azimuth(DomeGeometry(radius=2.0, east=0.5), 20.0, 0.0)
    far = slit_azimuth(DomeGeometry(radius=20.0, east=0.5), 20.0, 0.0)
    assert 0.0 < far < near < 30.0


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"radius": 0.0}, "key 'dome_radius': must be a positive number of metres, got 0.0"),
        ({"radius": float("nan")}, "key 'dome_radius'"),
        ({"radius": 2.0, "east": 1.5, "north": 1.5}, "key 'mount_offset': .* 2.121 m from the dome centre"),
    ],
)
def test_impossible_geometry_is_refused(kwargs: dict[str, float], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        DomeGeometry(**kwargs)


def test_dome_options_build_the_geometry_from_yaml_values() -> None:
    dome = build_object(
        {
            "class": "nightcrew.modules.sim.SimDome",
            "name": "dome",
            "dome_radius": 2.0,
            "mount_offset": [1, 0, 0.5],
        }
    )
    assert dome._geometry == DomeGeometry(radius=2.0, east=1.0, north=0.0, up=0.5)
    with pytest.raises(
        ConfigError, match="key 'dome_radius': an offset telescope needs the dome's radius too"
    ):
        build_object({"class": "nightcrew.modules.sim.SimDome", "name": "dome", "mount_offset": [1, 0, 0]})


async def test_dome_follows_an_offset_telescope_through_the_geometry(observatory: Observatory) -> None:
    telescope = await observatory.start(SimTelescope, "telescope")
    dome = await observatory.start(
        SimDome,
        "dome",
        follow="telescope",
        follow_interval=2.0,
        follow_tolerance=0.5,
        rotation_speed=10.0,
        dome_radius=2.0,
        mount_offset=(1.0, 0.0, 0.0),
    )
    await telescope.init()
    await telescope.move_altaz(20.0, 0.0)
    alt, az = await telescope.get_altaz()
    expected = slit_azimuth(DomeGeometry(radius=2.0, east=1.0), alt, az)
    assert expected > 25.0  # far from the telescope's own azimuth: following it would be wrong

    start = observatory.clock.time()
    while abs(azimuth_difference(await dome.get_azimuth(), expected)) > 0.5:
        assert observatory.clock.time() - start < 60.0, "dome did not turn to the slit azimuth"
        await observatory.clock.sleep(1.0)
