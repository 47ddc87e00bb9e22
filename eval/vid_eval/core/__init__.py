"""vid_eval.core: the metrics and their math (alignment, ATE/RPE, force, mass, phases, bounds); no file I/O, no plotting."""
