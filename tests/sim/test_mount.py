"""The simulated mount's error model and slew times."""

from __future__ import annotations

import numpy as np
import pytest

from nightcrew.sim.mount import MountErrorModel, apply_sky_offset, slew_time


def test_slew_time_is_linear_in_distance_plus_settling() -> None:
    assert slew_time(0.0, 4.0, 3.0) == 0.0
    assert slew_time(10.0, 4.0, 3.0) == pytest.approx(5.5)
    assert slew_time(40.0, 4.0, 3.0) - slew_time(20.0, 4.0, 3.0) == pytest.approx(5.0)
    with pytest.raises(ValueError, match="slew rate must be > 0 deg/s, got 0"):
        slew_time(10.0, 0.0)


def test_pointing_errors_have_the_configured_rms_and_repeat_with_the_seed() -> None:
    model = MountErrorModel(pointing_error=2.0)
    rng = np.random.default_rng(1)
    errors = [model.draw_slew_error(rng) for _ in range(4000)]
    east = np.array([e.east for e in errors]) * 60.0
    assert east.std() == pytest.approx(2.0, rel=0.05)
    again = MountErrorModel(pointing_error=2.0).draw_slew_error(np.random.default_rng(1))
    assert again == errors[0]


def test_drift_grows_with_tracking_time_and_periodic_error_repeats() -> None:
    model = MountErrorModel(pointing_error=0.0, drift_rate=6.0, periodic_amplitude=0.0)
    error = model.draw_slew_error(np.random.default_rng(0))
    east, north = model.offset(error, 600.0, 0.0)
    assert np.hypot(east, north) * 3600 == pytest.approx(60.0)  # 6"/min for 10 min
    periodic = MountErrorModel(
        pointing_error=0.0, drift_rate=0.0, periodic_amplitude=5.0, periodic_period=480.0
    )
    first = periodic.offset(error, 0.0, 1000.0)
    assert periodic.offset(error, 0.0, 1480.0) == pytest.approx(first)
    assert abs(periodic.offset(error, 0.0, 1120.0)[0]) * 3600 <= 5.0 + 1e-9


def test_model_refuses_negative_amplitudes() -> None:
    with pytest.raises(ValueError, match="drift_rate must be >= 0, got -1"):
        MountErrorModel(drift_rate=-1.0)


def test_sky_offsets_scale_with_declination() -> None:
    assert apply_sky_offset(10.0, 60.0, 0.5, 0.0) == pytest.approx((11.0, 60.0))
    assert apply_sky_offset(359.9, 0.0, 0.2, 0.1) == pytest.approx((0.1, 0.1), abs=1e-5)
