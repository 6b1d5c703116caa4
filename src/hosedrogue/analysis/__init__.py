"""Analysis of the hose-drogue model: equilibrium, linearization and model reduction."""
