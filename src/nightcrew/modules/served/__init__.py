"""Devices served to other protocols, written once by role, with an adapter per protocol beside them.

A role (:mod:`.camera`, :mod:`.focuser`) does the work on the nightcrew module behind a served
device; its adapters (:mod:`.camera_alpaca`, :mod:`.focuser_alpaca`; the INDI CCD and focuser in
:mod:`nightcrew.modules.indi.server_camera` and :mod:`nightcrew.modules.indi.server_motion`) only
translate their protocol's members or properties into calls of the role. The wire protocols themselves
(HTTP members, XML vectors) stay in ``nightcrew.bridges``, which never imports this package.
"""
