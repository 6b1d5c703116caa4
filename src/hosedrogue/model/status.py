"""Why a compiled run stopped: the one table of the reasons of the kernels' status codes
(:mod:`hosedrogue.model.layout`), which every loop reads (``simulate``, the fixed-length and the
engagement steppers, the engagement's driver, the fixed-length FMU's own RK4 loop) to write a
run's message (:func:`hosedrogue.results.run.stop_message`)."""

from __future__ import annotations

from . import layout as LY

__all__ = ["STATUS_TEXT", "status_text"]

#: A failing status code -> why the run stopped (one line).
STATUS_TEXT = {
    LY.NONFINITE: "the state became non-finite (numerical divergence)",
    LY.YAW_LIMIT: "a link's yaw passed the limit where the angle coordinates become singular",
    LY.STEP_LIMIT: "the adaptive integrator could not meet its tolerance (step size limit)",
    LY.STAGE_LIMIT: "the stiff integrator's stages did not converge, even on 16 substeps of a step (the step is too "
                    "long for the hose's motion: shorten numerics.step_s)",
    LY.REEL_END: "the free hose length left the reel's range between its end stops (fully reeled in or fully "
                 "paid out)",
}


def status_text(code: int, params=None) -> str:
    """Why a run stopped with a failing status code.

    Parameters
    ----------
    code : int
        A failing code of :data:`STATUS_TEXT`.
    params : hosedrogue.spec.params.Params, optional
        The fixed-length hose's parameters: a yaw past the limit of the paper's hose (its bending
        law) then adds the likely cause, its almost undamped zigzag modes (in turbulence, when it is
        on), and the cure.

    Returns
    -------
    str
        One line.
    """
    text = STATUS_TEXT[code]
    if params is not None and code == LY.YAW_LIMIT and params.hose.bending == "paper":
        where = " in turbulence" if params.turbulence.enabled else ""
        text += (f" (likely the paper's almost undamped zigzag modes growing{where}; for long runs use the model "
                 "preset: --config converged or [model] preset = \"converged\", docs/long-runs.md)")
    return text
