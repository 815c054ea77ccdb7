"""Stand-alone servers that modules and tools talk to over HTTP: the image archive
(:mod:`nightcrew.services.archive`) and the plate-solving service (:mod:`nightcrew.services.solver`)."""
