"""Observing scripts the task runner picks by configuration type.

=====================  =====================  ================================================================
script                 runner key             modules (constructor parameters, default names)
=====================  =====================  ================================================================
ImagingScript          EXPOSE, REPEAT_EXPOSE  telescope, camera, filters; acquisition, autoguider, focuser
CalibrationScript      BIAS, DARK             camera
AutoFocusScript        AUTO_FOCUS             focus, telescope, filters (+ ``step`` in mm)
SkyFlatScript          SKY_FLAT               flatfield
PanelFlatScript        PANEL_FLAT             camera, filters, calibrator
PointingSeriesScript   SCRIPT:<name>          pointing
=====================  =====================  ================================================================

Every script reaches the devices through proxies only, reports progress after every exposure (or
series a module takes), takes only what the task's recorded progress still lacks (a retry after an
interruption does not repeat frames already taken), names the failing step in its
:class:`~nightcrew.robotic.runner.ScriptError` and, when cancelled, aborts what runs (exposure,
slew, series) and stops guiding before re-raising. The imaging script also dithers, grades its
frames (taking failed ones again) and refocuses between frames when asked to (see
:mod:`nightcrew.robotic.scripts._between`).
"""

from nightcrew.robotic.scripts._dither import dither_field_problems
from nightcrew.robotic.scripts.autofocus import AutoFocusScript, focus_step
from nightcrew.robotic.scripts.calibration import CalibrationScript
from nightcrew.robotic.scripts.imaging import ImagingScript
from nightcrew.robotic.scripts.panelflat import PanelFlatScript
from nightcrew.robotic.scripts.pointing import PointingSeriesScript
from nightcrew.robotic.scripts.skyflat import SkyFlatScript

__all__ = [
    "AutoFocusScript",
    "CalibrationScript",
    "ImagingScript",
    "PanelFlatScript",
    "PointingSeriesScript",
    "SkyFlatScript",
    "dither_field_problems",
    "focus_step",
]
