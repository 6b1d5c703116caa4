"""hosedrogue: the probe-and-drogue aerial refuelling hose as a Kane-equation chain of rigid
links (after Wu et al., 2018), with its air environment, equilibrium, linearization, model
reduction and PID/LQR control.

Quick start::

    from hosedrogue import PAPER, solve_equilibrium, simulate
    eq = solve_equilibrium(PAPER)
    res = simulate(PAPER, duration_s=5.0)
"""

from .version import __version__
from .config import load_params, resolve_config
from .params import PAPER, Params, ParameterError

__all__ = ["PAPER", "Params", "ParameterError", "load_params", "resolve_config", "solve_equilibrium", "simulate", "__version__"]


def __getattr__(name):
    # heavy modules (numba compilation) load on first use
    if name == "solve_equilibrium":
        from .analysis.equilibrium import solve_equilibrium

        return solve_equilibrium
    if name == "simulate":
        from .simulation import simulate

        return simulate
    raise AttributeError(name)
