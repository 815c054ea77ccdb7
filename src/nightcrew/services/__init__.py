"""Stand-alone servers that modules and tools talk to over HTTP (the plate-solving service, ...)."""
