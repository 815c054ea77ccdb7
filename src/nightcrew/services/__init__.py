"""Stand-alone servers: the image archive (:mod:`nightcrew.services.archive`)."""
