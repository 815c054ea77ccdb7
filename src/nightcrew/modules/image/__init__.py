"""Images on disk: ImageWriter (copy on NewImageEvent), ImageWatcher (move files from a local
directory, losing none) and HttpFileCache (a small HTTP file store; the HttpFile VFS root talks to it)."""

from nightcrew.modules.image.seeing import Seeing
from nightcrew.modules.image.watcher import ImageWatcher
from nightcrew.modules.image.writer import ImageWriter

__all__ = ["ImageWatcher", "ImageWriter", "Seeing"]
