"""Moving bodies on a solved frame: the body's position measured where its ephemeris (the frame's
``EPH-*`` cards) says it is at mid-exposure, and the MPC observation line of that measurement."""

from nightcrew.images.processors.moving._measure import (
    MOVING_CARDS,
    MeasureMovingBody,
    MovingBodyMeasurement,
    measure_moving_body,
    mpc_line_of,
    predicted_position,
)

__all__ = [
    "MOVING_CARDS",
    "MeasureMovingBody",
    "MovingBodyMeasurement",
    "measure_moving_body",
    "mpc_line_of",
    "predicted_position",
]
