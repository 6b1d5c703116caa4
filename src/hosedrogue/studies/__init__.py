"""Studies: many simulations driven towards one question.

* :mod:`.campaign` - Monte Carlo campaigns over turbulence seeds (:func:`run_campaign`), with
  :mod:`.seeds` (run seeds), :mod:`.store` (the campaign's files), :mod:`.executor` (dask or this
  process) and :mod:`.statistics` (the summary over runs);
* :mod:`.convergence` - integration step and link count convergence;
* :mod:`.accuracy` - accuracy against the number of links for both mass lumpings, against the
  continuum limit;
* :mod:`.long_runs` - time to blow-up of the paper's model, the least damped mode per model
  option, and the stable model's hour-long run.
"""
