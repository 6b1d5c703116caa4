"""Scenarios of the viewer's tests (tests/viewer/test_viewer.py, tests/viewer/test_viewer_browser.py): short runs
of both hose models, seconds each once compiled."""

#: 6 links, 1.5 s, turbulence from 0.2 s: a run takes tens of milliseconds once compiled.
TINY = """\
[scenario]
name = "tiny-swing"
duration_s = 1.5

[turbulence]
enabled = true
start_s = 0.2
duration_s = 1.3

[hose]
links = 6
"""

#: engage-response on 20 rigid links of 0.8 m (RK4, the former 0.625 ms step scaled with the link
#: length) for 3.5 s: contact at 2 s, then the reel takes up the slack and two links merge (at 2.68 s
#: and 3.24 s). Rigid, so that the links' lengths sum to the free hose length (an elastic hose is
#: longer by its stretch).
ENGAGE = """\
[scenario]
extends = "engage-response"
name = "engage-response-20"
duration_s = 3.5

[hose]
links = 20
axial_stiffness_n = inf
axial_damping_n_s = 0.0

[numerics]
integrator = "rk4"
step_s = 0.005
output_every = 2
"""
