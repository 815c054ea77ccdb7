"""Image processors, one subpackage per task: ``detection``, ``photometry``, ``offsets``,
``exptime`` and ``misc``. Shared pixel helpers live in :mod:`._shared`."""
