"""alpaca-simulators with devices its template lacks, for the dome and cover-calibrator tests.

Added to the template: dome 1, a roll-off roof (a Dome device that cannot turn); cover-calibrator
0 gets a light (the template's has none), and cover-calibrator 1 is a flat panel without a cover.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path
from typing import Any

import yaml

from nightcrew.testing.alpaca import TEST_OVERRIDES, AlpacaSimulator, start_simulator

DOME, ROLL_OFF_ROOF = 0, 1
FLIP_FLAT, PANEL = 0, 1


def _template_device(device_type: str) -> dict[str, Any]:
    template = resources.files("alpaca_simulators").joinpath("config/template.yaml").read_text()
    device: dict[str, Any] = yaml.safe_load(template)["devices"][device_type][0]
    return device


def start_with_more_devices(directory: Path, star_table: Path) -> AlpacaSimulator:
    """A private alpaca-simulators (stop it after) with the devices above."""
    roof = {
        **_template_device("dome"),
        "name": "Roll-off roof",
        "cansetazimuth": False,
        "cansetaltitude": False,
        "canslave": False,
        "canfindhome": False,
    }
    cover = _template_device("covercalibrator")
    overrides = {
        **TEST_OVERRIDES,
        "devices": {
            **TEST_OVERRIDES["devices"],
            "dome": {ROLL_OFF_ROOF: roof},
            "covercalibrator": {
                FLIP_FLAT: {"calibratorstate": 1},  # 1: Off, i.e. there is a light
                PANEL: {**cover, "name": "Flat panel", "coverstate": 0, "calibratorstate": 1},
            },
        },
    }
    return start_simulator(directory, star_table=star_table, overrides=overrides)
