"""Observing scripts the task runner picks by configuration type.

=================  ==============================  =============================================
script             configuration types             modules (constructor parameters)
=================  ==============================  =============================================
ImagingScript      EXPOSE, REPEAT_EXPOSE           telescope, camera, filters, acquisition,
                                                   autoguider
=================  ==============================  =============================================
"""

from nightcrew.robotic.scripts.imaging import ImagingScript

__all__ = ["ImagingScript"]
