"""Interoperability with the tools people already use: FMI 2.0 co-simulation FMUs
(:mod:`.fmu`, :mod:`.fmu_slave`) and MATLAB ``.mat`` files (:mod:`.matlab`)."""
