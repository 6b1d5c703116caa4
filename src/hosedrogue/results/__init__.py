"""What a run gives: the result objects of a fixed-length run and of an engagement (:mod:`.run`),
the drogue's window statistics and their compiled accumulator (:mod:`.statistics`), the actuated
drogue's surface histories (:mod:`.surfaces`), the hose's shapes file (:mod:`.hose_file`), and which
engagement loads are converged (:mod:`.convergence`)."""
