"""Studies built on the model: accuracy against the number of links (``accuracy``)."""
