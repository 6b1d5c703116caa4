"""The air the hose flies through: standard atmosphere, tanker wake and Dryden turbulence.

Modules
-------
atmosphere
    ICAO standard atmosphere (density at the flight altitude).
wake
    Hallock-Burnham trailing-vortex pair of the tanker (docs/model.md §4); a numba kernel
    :func:`~hosedrogue.environment.wake.wake_velocity` for the inner loop.
dryden
    Dryden spectra, forming filters and their exact discretization.
turbulence
    The gust record drawn through the Dryden filters (re-exporting :mod:`.dryden`); a numba lookup
    :func:`~hosedrogue.environment.turbulence.gust_at` for the inner loop.

All velocities are in m/s along the tanker trajectory frame S_p (x forward, y right, z down),
positions in metres relative to the tow point.
"""
