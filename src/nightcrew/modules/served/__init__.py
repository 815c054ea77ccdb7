"""Devices served to other protocols, written once by role, with an adapter per protocol beside them.

A role (:mod:`.camera`, :mod:`.focuser`, :mod:`.filterwheel`, :mod:`.dome`) does the work on the
nightcrew module behind a served device; its adapters (``<role>_alpaca``, ``<role>_indi``) only
translate their protocol's members or properties into calls of the role. :mod:`.device_indi` is
the base of every INDI adapter (also of the INDI telescope, still in ``modules/indi``). The wire
protocols themselves (HTTP members, XML vectors) stay in ``nightcrew.bridges``, which never
imports this package.
"""
