"""Table 3's steps (hosedrogue.controllers.table3, .stepinfo) through the compiled step response
(hosedrogue.analysis.responses.step_outputs) are python-control's step responses of the same
loops, byte for byte: the PID's unity-feedback loops and the balanced-state LQR's two-input loop,
output and control force."""

import numpy as np
import control

from hosedrogue.controllers.lqr_balanced import lqr_balanced_design, lqr_balanced_reference_loop
from hosedrogue.controllers.pid import PAPER_PID
from hosedrogue.controllers.table3 import channel_models, lqr_steps, pid_steps
from hosedrogue.spec.paper import CHANNELS


def test_pid_steps_are_python_controls_bits():
    lat, ver = channel_models("paper", 2)
    steps = pid_steps(lat, ver)
    for ch, g in zip(CHANNELS, (lat, ver)):
        c = control.ss(PAPER_PID[ch].transfer_function())
        g = control.ss(g)
        t = steps[ch].t_s
        y = control.step_response(control.feedback(control.series(c, g), 1), t).outputs
        u = control.step_response(control.feedback(c, g), t).outputs
        assert steps[ch].y.tobytes() == np.asarray(y).tobytes()
        assert steps[ch].u.tobytes() == np.asarray(u).tobytes()


def test_lqr_steps_are_python_controls_bits():
    design = lqr_balanced_design(*channel_models("paper", 2))
    steps = lqr_steps(design)
    loop = lqr_balanced_reference_loop(design)
    for k, ch in enumerate(CHANNELS):
        out = control.step_response(loop, steps[ch].t_s, input=k, squeeze=False).outputs
        assert steps[ch].y.tobytes() == out[k, 0].tobytes()
        assert steps[ch].u.tobytes() == out[2 + k, 0].tobytes()
