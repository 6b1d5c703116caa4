"""Compiled core of the engagement (numba): a hose of varying free length on a reel, and the probe.

The chain is the one of :mod:`hosedrogue.model.chain_loads` and
:mod:`hosedrogue.model.chain_dynamics` with one change: link 0 (the exit link, from the hose exit
to joint 1) has the variable length ``l_0 = L - sum_{k>=1} l_k``, L the free hose length, a
generalized coordinate of its own (docs/model.md, "Hose of varying length"). Joints 1..n are
material points of the hose. Every joint's velocity gains ``L' e_0`` and every joint's
acceleration ``L'' e_0 + 2 L' de_0/dt``. The existing kernels are reused unchanged:

* :func:`~hosedrogue.model.chain_loads.joint_kinematics` gives positions, velocities and the
  velocity-product accelerations of the fixed-length chain;
  :func:`~hosedrogue.model.engagement.chain.patch_kinematics` adds the ``L' e_0`` velocity (also
  to joint 0: the hose material leaves the exit at ``L' e_0``, which the exit link's drag sees)
  and the Coriolis-like ``2 L' de_0/dt`` term;
* the term ``L'' e_0`` is the same for every joint 1..n, so it acts on the chain like an
  acceleration of its root. The dynamics are linear in it: one articulated-body solve
  (:func:`~hosedrogue.model.chain_dynamics.chain_forward_dynamics`) with the real loads gives qdd
  and the hose's pull ``P_0`` at L'' = 0; a second with only the d'Alembert forces ``-M_k e_0``
  gives the response per unit L''. The exit tension ``T_0 = P . e_0`` is the generalized force
  of the hose on L; the reel equation closes the system for L''. Still O(n).

State ``z = [q (2n), qd (2n), L, L', W_motor, W_friction, W_exit, W_flux, W_probe]``: the five
last entries integrate powers for the energy balance (work of the motor on the drum, heat of the
drum's friction, work of the exit on the hose, kinetic energy carried by hose joining or leaving
the moving masses, work of the probe on the drogue; the tail's slots ``Z_*``, and the ``EP_*`` of
``ep``, the engagement scalars, are declared in :mod:`hosedrogue.model.layout`); ``ws`` is
:func:`~hosedrogue.model.chain_dynamics.make_workspace` of n links and ``ws2`` a second one for
the unit-L'' solve.

The modules, each importing only those before it:

* :mod:`.chain` - the state's tail, the exit link's length and masses from L, the angle charts,
  the kinematics with the reel's terms;
* :mod:`.probe` - the probe tip's path (prescribed, fed, or flown), the coupling's force, the
  bow wave in an evaluation's air;
* :mod:`.reel` - the reel's laws, its outputs and the powers;
* :mod:`.pilot` - the pilot's and the receiver's states;
* :mod:`.evaluation` - the evaluations of the rigid and the elastic chain and dz/dt;
* :mod:`.outputs` - the outputs at saved states, energies, per-step loads, the raw measurement,
  the coupler plane;
* :mod:`.steps` - the RK4 and SDIRK steps, the segments of steps the driver runs.
"""
