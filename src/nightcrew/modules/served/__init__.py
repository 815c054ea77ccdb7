"""Devices served to other protocols, written once by role, with an adapter per protocol beside them.

A role (:mod:`.camera`) does the work on the nightcrew module behind a served device; its adapters
(:mod:`.camera_alpaca`; the INDI CCD in :mod:`nightcrew.modules.indi.server_camera`) only translate
their protocol's members or properties into calls of the role. The wire protocols themselves
(HTTP members, XML vectors) stay in ``nightcrew.bridges``, which never imports this package.
"""
