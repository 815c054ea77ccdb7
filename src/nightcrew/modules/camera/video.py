"""Video cameras: a camera with a live stream; grab_data saves a frame like any camera."""

from __future__ import annotations

from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.interfaces import IVideo
from nightcrew.modules.camera.base import BaseCamera

__all__ = ["BaseVideo"]


class BaseVideo(BaseCamera, IVideo):
    """A camera that also offers a video stream (e.g. a guide or all-sky camera).

    Args:
        video_url: Where the stream can be watched (http://, rtsp://, ...).
        **kwargs: Camera options.
    """

    def __init__(self, *, video_url: str, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if "://" not in video_url:
            raise ConfigError(
                f"expected a URL like http://host:8080/stream, got {video_url!r}", key="video_url"
            )
        self._video_url = video_url

    async def get_video(self) -> str:
        return self._video_url
