"""The pointing model a telescope applies between the requested and the commanded position.

A telescope configured with ``pointing_model: FILE`` (a YAML or JSON file written by
``nightcrew pointing fit`` or by the passive refit, :mod:`nightcrew.modules.pointing.refit`) sends
the mount to :meth:`PointingModel.to_mount` of each requested RA/Dec (moves and offsets; Alt/Az
moves are left alone) and reports :meth:`PointingModel.to_sky` of the mount's position, so
``get_radec`` and the frames' RA/DEC say where the telescope really points. Frames also get the
mount's own position (``MNT-RA``, ``MNT-DEC``), the pairs the refit needs.

The file is read when the telescope is built (a file for another mount, unknown terms or a broken
file are one ConfigError naming the file, so ``nightcrew check`` reports them) and read again when
it changes (a refit replaced it); a missing file means no model yet. A file that turns bad later is
logged and the model in use is kept.
"""

from __future__ import annotations

import json
import logging
import os
from pathlib import Path

import yaml

from nightcrew.astro.pointing import PointingModel, PointingModelError
from nightcrew.config import load_data_file
from nightcrew.errors import ConfigError
from nightcrew.interfaces import FitsCard
from nightcrew.site import Site

__all__ = ["TelescopePointingModel", "load_pointing_model", "save_pointing_model"]

log = logging.getLogger(__name__)


def load_pointing_model(path: str | os.PathLike[str], mount: str) -> PointingModel:
    """The model in ``path`` for ``mount``; ConfigError naming the file for anything wrong."""
    try:
        return PointingModel.from_dict(load_data_file(path), mount=mount)
    except PointingModelError as exc:
        raise ConfigError(str(exc), file=os.fspath(path)) from exc
    except OSError as exc:
        raise ConfigError(
            f"cannot read the pointing model: {exc.strerror or exc}", file=os.fspath(path)
        ) from exc


def save_pointing_model(path: str | os.PathLike[str], model: PointingModel) -> None:
    """Write the model as YAML (JSON for a ``.json`` name) whole or not at all."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    data = model.to_dict()
    if target.suffix.lower() == ".json":
        text = json.dumps(data, indent=2) + "\n"
    else:
        text = yaml.safe_dump(data, sort_keys=False)
    partial = target.with_name(target.name + ".partial")
    partial.write_text(text, encoding="utf-8")
    os.replace(partial, target)


class TelescopePointingModel:
    """The model of one telescope, read from its file (see the module docstring); no file: identity.

    Args:
        path: The model file; None: no model.
        mount: Name of the telescope module (the file must be for it).
        site: The observatory (hour angles need the longitude).
    """

    def __init__(self, path: str | None, mount: str, site: Site) -> None:
        self._path, self._mount, self._site = path, mount, site
        self._model: PointingModel | None = None
        self._stamp: tuple[int, int] | None = None
        if path is not None:
            if Path(path).exists():
                self._model = load_pointing_model(path, mount)
                self._stamp = _stamp(path)
            else:
                log.warning("%s: no pointing model in %s yet: pointing uncorrected", mount, path)

    @property
    def model(self) -> PointingModel | None:
        """The model in use (read again first if its file changed)."""
        self._reload_if_changed()
        return self._model

    def _reload_if_changed(self) -> None:
        if self._path is None:
            return
        stamp = _stamp(self._path)
        if stamp is None or stamp == self._stamp:
            return
        self._stamp = stamp
        try:
            self._model = load_pointing_model(self._path, self._mount)
        except ConfigError as exc:
            log.error("%s: pointing model not replaced: %s", self._mount, exc)
            return
        log.info("%s: pointing model read from %s: %s", self._mount, self._path, _describe(self._model))

    def to_mount(self, ra: float, dec: float, unix_time: float) -> tuple[float, float]:
        """The ICRS position to send the mount to so that it points at ICRS (ra, dec)."""
        model = self.model
        return (ra, dec) if model is None else model.to_mount_icrs(ra, dec, self._site.longitude, unix_time)

    def to_sky(self, ra: float, dec: float, unix_time: float) -> tuple[float, float]:
        """Where the telescope points when the mount reports ICRS (ra, dec)."""
        model = self._model
        return (ra, dec) if model is None else model.to_sky_icrs(ra, dec, self._site.longitude, unix_time)

    def cards(self, mount_radec: tuple[float, float]) -> dict[str, FitsCard]:
        """The mount's own position, when a model corrects it (none otherwise)."""
        if self._model is None:
            return {}
        return {
            "MNT-RA": (round(mount_radec[0], 6), "Mount right ascension, before the pointing model [deg]"),
            "MNT-DEC": (round(mount_radec[1], 6), "Mount declination, before the pointing model [deg]"),
        }


def _stamp(path: str) -> tuple[int, int] | None:
    try:
        status = os.stat(path)
    except OSError:
        return None
    return status.st_mtime_ns, status.st_size


def _describe(model: PointingModel) -> str:
    fit = model.statistics
    terms = ", ".join(f"{name} {value:.1f}" for name, value in model.terms.items())
    return terms + (f' (fit RMS {fit.rms_after:.1f}" on {fit.points} points)' if fit else "")
