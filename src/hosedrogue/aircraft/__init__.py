"""The receiver as an aircraft: a rigid body in six degrees of freedom with a table-driven
aerodynamic and engine model read from a file (the F-16 of Stevens, Lewis & Johnson, 2015, is
shipped), its trim anywhere in the envelope and its linear model with its modes (docs/receiver.md).
"""
