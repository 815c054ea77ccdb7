"""nightcrew.events: the catalogue of events modules send and receive.

Importing this package registers every event class, so :func:`event_by_name` knows every name.
"""

from nightcrew.events.base import Event, event_by_name, hardware_event_names
from nightcrew.events.focus import FocusFailedEvent, FocusFoundEvent
from nightcrew.events.image import ExposureStatusChangedEvent, NewImageEvent, NewSpectrumEvent
from nightcrew.events.log import LogEvent
from nightcrew.events.module import ModuleClosedEvent, ModuleOpenedEvent, ModuleStateChangedEvent
from nightcrew.events.motion import FilterChangedEvent, MotionStatusChangedEvent
from nightcrew.events.pointing import MoveAltAzEvent, MoveRaDecEvent, OffsetsAltAzEvent, OffsetsRaDecEvent
from nightcrew.events.roof import RoofClosedEvent, RoofClosingEvent, RoofOpenedEvent
from nightcrew.events.safety import SafetyAlarmEvent, SafetyClearedEvent, WatchdogHeartbeatEvent
from nightcrew.events.task import (
    RapidResponseEvent,
    ScheduleChangedEvent,
    TaskFailedEvent,
    TaskFinishedEvent,
    TasksChangedEvent,
    TaskStartedEvent,
)
from nightcrew.events.test import TestEvent
from nightcrew.events.weather import BadWeatherEvent, GoodWeatherEvent

__all__ = [
    "BadWeatherEvent",
    "Event",
    "ExposureStatusChangedEvent",
    "FilterChangedEvent",
    "FocusFailedEvent",
    "FocusFoundEvent",
    "GoodWeatherEvent",
    "LogEvent",
    "ModuleClosedEvent",
    "ModuleOpenedEvent",
    "ModuleStateChangedEvent",
    "MotionStatusChangedEvent",
    "MoveAltAzEvent",
    "MoveRaDecEvent",
    "NewImageEvent",
    "NewSpectrumEvent",
    "OffsetsAltAzEvent",
    "OffsetsRaDecEvent",
    "RapidResponseEvent",
    "RoofClosedEvent",
    "RoofClosingEvent",
    "RoofOpenedEvent",
    "SafetyAlarmEvent",
    "SafetyClearedEvent",
    "ScheduleChangedEvent",
    "TaskFailedEvent",
    "TaskFinishedEvent",
    "TaskStartedEvent",
    "TasksChangedEvent",
    "TestEvent",
    "WatchdogHeartbeatEvent",
    "event_by_name",
    "hardware_event_names",
]
