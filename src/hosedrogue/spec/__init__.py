"""What a run is made of: the model's parameters and their sections (:mod:`.params`), the control
loop's and the engagement's run sections (:mod:`.sections`, :mod:`.drogue_surfaces`), the tanker's
manoeuvres (:mod:`.manoeuvres`), the standard turbulence intensities (:mod:`.standards`), the shipped
presets and config files (:mod:`.config`), and the field validator they are all written with
(:mod:`.fields`)."""
