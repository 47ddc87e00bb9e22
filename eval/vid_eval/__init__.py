"""VID-MSCKF evaluation package: trajectory, force and mass metrics, plots, tables, bag conversion."""
__version__ = "0.1.0"
