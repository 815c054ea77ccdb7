"""The one night engine: the bundled observatory built in one process and run through a night.

- :mod:`~nightcrew.night.build`: build the modules of a directory of module files on one network
  and clock (:func:`~nightcrew.night.build.bundled_observatory` is the bundled one), park and close.
- :mod:`~nightcrew.night.engine`: run the robotic night (scheduler + mastermind) until its end.
- :mod:`~nightcrew.night.plan`, :mod:`~nightcrew.night.fields`: the night's span, weather
  scenarios and task lists (the samples, the survey, the ``--quick`` preset).
- :mod:`~nightcrew.night.blocks`: NightBlockSource, the archive block source under its old name.
- :mod:`~nightcrew.night.recorder`: the module that writes every event to events.jsonl.
"""
