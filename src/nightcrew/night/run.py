"""``nightcrew sim`` behind its options: a night, a season of nights, or the devices served to Alpaca."""

from __future__ import annotations

from nightcrew.errors import ConfigError
from nightcrew.night.options import SimOptions

__all__ = ["run_sim"]


def run_sim(options: SimOptions) -> int:
    """Run what ``options`` ask for; the command's exit code."""
    # The heavier imports (the observatory, the engine) only for the mode that runs.
    if options.alpaca is not None:
        from nightcrew.night.alpaca import serve_alpaca

        return serve_alpaca(options)
    if options.archive and options.nights > 1:
        raise ConfigError("--archive archives one night; leave out --nights")
    if options.nights > 1:
        from nightcrew.night.season import run_season

        return run_season(options)
    from nightcrew.night.sim import run_night

    return run_night(options)
