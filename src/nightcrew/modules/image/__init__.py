"""Modules that work on images other modules took: Seeing (FWHM of new frames); images on disk:
ImageWriter (copy on NewImageEvent), ImageWatcher (move files from a local directory, losing none)
and HttpFileCache (a small HTTP file store; the HttpFile VFS root talks to it); Pipeline (the
online reduction of every new science frame)."""

from nightcrew.modules.image.http_cache import FileCacheServer, HttpFileCache
from nightcrew.modules.image.pipeline import Pipeline
from nightcrew.modules.image.seeing import Seeing
from nightcrew.modules.image.watcher import ImageWatcher
from nightcrew.modules.image.writer import ImageWriter

__all__ = ["FileCacheServer", "HttpFileCache", "ImageWatcher", "ImageWriter", "Pipeline", "Seeing"]
