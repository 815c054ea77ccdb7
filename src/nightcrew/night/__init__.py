"""The one night engine and ``nightcrew sim``: an observatory directory built in one process and
run through a night.

- :mod:`~nightcrew.night.options`: :class:`~nightcrew.night.options.SimOptions`, all that
  ``nightcrew sim`` is asked for; :mod:`~nightcrew.night.run` runs it (a night, a season of
  nights: :mod:`~nightcrew.night.sim`, :mod:`~nightcrew.night.season`; the devices served to Alpaca
  clients: :mod:`~nightcrew.night.alpaca`).
- :mod:`~nightcrew.night.build`: build the modules of a directory of module files on one network
  and clock (:func:`~nightcrew.night.build.bundled_observatory` is ``examples/observatory``), park
  and close.
- :mod:`~nightcrew.night.engine`: run the robotic night (scheduler + mastermind) until its end.
- :mod:`~nightcrew.night.plan`, :mod:`~nightcrew.night.fields`: the night's span, weather
  scenarios and task lists (the samples, the survey, the ``--quick`` preset).
- :mod:`~nightcrew.night.blocks`: NightBlockSource, the archive block source under its old name.
- :mod:`~nightcrew.night.recorder`: the module that writes every event to events.jsonl.
- :mod:`~nightcrew.night.console`, :mod:`~nightcrew.night.pipeline`, :mod:`~nightcrew.night.archive`:
  what ``--console`` and ``--archive`` add.
"""
