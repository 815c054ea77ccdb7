"""nightcrew.testing's public surface is what its docstring promises, nothing more."""

from __future__ import annotations

import nightcrew.testing


def test_exported_members() -> None:
    assert sorted(nightcrew.testing.__all__) == sorted(
        [
            "EPOCH",
            "SITE",
            "CameraContract",
            "Condition",
            "ContractProbe",
            "ContractSetup",
            "CoverCalibratorContract",
            "DeviceContract",
            "DomeContract",
            "EventRecorder",
            "FilterWheelContract",
            "FocuserContract",
            "Observatory",
            "RoofContract",
            "RotatorContract",
            "SwitchContract",
            "TelescopeContract",
            "WeatherStationContract",
            "modules_ready",
            "timed_call",
            "wait_for",
        ]
    )
    missing = [name for name in nightcrew.testing.__all__ if not hasattr(nightcrew.testing, name)]
    assert missing == []
