"""Studies: many simulations driven towards one question.

* :mod:`.campaign` - Monte Carlo campaigns over turbulence seeds (:func:`run_campaign`), with
  :mod:`.seeds` (run seeds), :mod:`.store` (the campaign's files), :mod:`.executor` (dask or this
  process) and :mod:`.statistics` (the summary over runs);
* :mod:`.convergence` - integration step and link count convergence;
* :mod:`.accuracy` - accuracy against the number of links for both mass lumpings, against the
  continuum limit;
* :mod:`.long_runs` - time to blow-up of the paper's model, the least damped mode per model
  option, and the stable model's hour-long run;
* :mod:`.docking` - the capture rate of the approach scenarios per cell of a grid (turbulence
  level x drogue controller x bow wave, the pilot, the closure speed, the force limit), one
  campaign per cell (:func:`.docking.run_grid`), with :mod:`.docking_grid` (the cells and their
  scenarios) and :mod:`.docking_statistics` (tables, comparisons, saturation, findings);
* :mod:`.bow_wave` - the receiver's bow-wave field and the drogue's steady displacement;
* :mod:`.pid_tuning` - a PID tuned to Table 3's step figures against the paper's Eq. 33 gains, on
  the paper's models and this model (linear steps and the turbulence case).
"""
