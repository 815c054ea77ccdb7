"""Devices served to other protocols, written once by role, with an adapter per protocol beside them.

A role (:mod:`.camera`, :mod:`.focuser`) does the work on the nightcrew module behind a served
device; its adapters (:mod:`.camera_alpaca` and :mod:`.camera_indi`, :mod:`.focuser_alpaca` and
:mod:`.focuser_indi`) only translate their protocol's members or properties into calls of the
role. :mod:`.device_indi` is the base of every INDI
adapter (the INDI telescope, focuser, filter wheel and dome in ``modules/indi`` too). The wire
protocols themselves (HTTP members, XML vectors) stay in ``nightcrew.bridges``, which never imports
this package.
"""
