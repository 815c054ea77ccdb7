"""Pure simulation core: star catalog, projection, sky and camera physics, frame rendering.

Everything here is synchronous numpy/astropy code without comm, clock or I/O (except reading the
bundled catalog packages' data files). Device modules build on these functions. Import the
submodules directly (``from nightcrew.sim.render import render_frame``); this package ``__init__``
imports nothing so that ``import nightcrew`` stays light.
"""
