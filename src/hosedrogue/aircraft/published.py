"""Published numbers of the F-16 model of Stevens, Lewis & Johnson, *Aircraft Control and
Simulation*, 3rd ed., Wiley, 2015, for comparison (the book's own units: ft, s, deg or rad as
printed). Values as transcribed in the tests of github.com/AlexS12/FlightMechanicsSimulator.jl
(test/f16/sixdof.jl, test/f16/trimmer.jl, test/f16/simulation.jl, with the book's page numbers);
Table 3.5-2 and Example 3.6-2 are also in the tests of github.com/PineTreeLabs/archimedes
(examples/f16/test_f16.py), and agree.
"""

from __future__ import annotations

#: Table 3.5-2 (p. 185): the state derivative at one state, xcg = 0.4, the book's g = 32.17 ft/s^2.
#: State: airspeed [ft/s], alpha, beta, phi, theta, psi [rad], p, q, r [rad/s], north, east [ft],
#: altitude [ft], power [%]; controls: throttle [-], elevator, aileron, rudder [deg].
TABLE_3_5_2 = {
    "xcg": 0.4,
    "state": (500.0, 0.5, -0.2, -1.0, 1.0, -1.0, 0.7, -0.8, 0.9, 1000.0, 900.0, 10000.0, 90.0),
    "controls": (0.9, 20.0, -15.0, -20.0),
    "derivative": (-75.23724, -0.8813491, -0.4759990, 2.505734, 0.3250820, 2.145926, 12.62679, 0.9649671,
                   0.5809759, 342.4439, -266.7707, 248.1241, -58.68999),
}

#: The book's g [ft/s^2] (its F16 subroutine, GD = 32.17).
G_BOOK_FT_S2 = 32.17

#: The book's inertia constants C1..C9 of its F16 subroutine (Section 3.5, printed to 4 digits),
#: from AXX = 9496, AYY = 55814, AZZ = 63100, AXZ = 982 slug ft^2.
BOOK_INERTIA_CONSTANTS = (-0.770, 0.02755, 1.055e-4, 1.642e-6, 0.9604, 1.759e-2, 1.792e-5, -0.7336, 1.587e-5)

#: Table 3.6-2 (p. 193): steady level flight at sea level, xcg = 0.35. Rows: airspeed [ft/s],
#: throttle [-], alpha [deg], elevator [deg], as printed (3 significant digits). The transcription
#: holds these 16 speeds from 130 to 800 ft/s.
TABLE_3_6_2 = (
    (130.0, 0.816, 45.6, 20.1),
    (140.0, 0.736, 40.3, -1.36),
    (150.0, 0.619, 34.6, 0.173),
    (170.0, 0.464, 27.2, 0.621),
    (200.0, 0.287, 19.7, 0.723),
    (260.0, 0.148, 11.6, -0.09),
    (300.0, 0.122, 8.49, -0.591),
    (350.0, 0.107, 5.87, -0.539),
    (400.0, 0.108, 4.16, -0.591),
    (440.0, 0.113, 3.19, -0.671),
    (500.0, 0.137, 2.14, -0.756),
    (540.0, 0.160, 1.63, -0.798),
    (600.0, 0.200, 1.04, -0.846),
    (640.0, 0.230, 0.742, -0.871),
    (700.0, 0.282, 0.382, -0.900),
    (800.0, 0.378, -0.045, -0.943),
)

#: Table 3.6-3 (p. 195): trim at 502 ft/s, sea level, level flight, for three centres of gravity.
#: xcg -> (alpha [rad], throttle [-], elevator [deg]), as printed.
TABLE_3_6_3 = {
    0.35: (0.03691, 0.1385, -0.7588),
    0.30: (0.03936, 0.1485, -1.931),
    0.38: (0.03544, 0.1325, -0.05590),
}

#: Example 3.6-2 (pp. 191-192): a coordinated turn at 502 ft/s, sea level, xcg = 0.35, turn rate
#: 0.3 rad/s. State as in TABLE_3_5_2 (power [%]), controls throttle [-], elevator, aileron, rudder [deg].
EXAMPLE_3_6_2 = {
    "xcg": 0.35,
    "turn_rate_rad_s": 0.3,
    "state": (502.0, 0.2392628, 5.061803e-4, 1.366289, 5.000808e-2, 0.2340769, -1.499617e-2, 0.2933811,
              6.084932e-2, 0.0, 0.0, 0.0, 64.12363),
    "controls": (0.8349601, -1.481766, 9.553108e-2, -0.4118124),
}
