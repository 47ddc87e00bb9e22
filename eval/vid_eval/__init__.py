"""VID-MSCKF evaluation package: trajectory, force and mass metrics, plots, tables, bag conversion."""
from importlib import metadata as _metadata

try:  # the installed distribution's version: from git (setuptools-scm) at build time
    __version__ = _metadata.version("vid-eval")
except _metadata.PackageNotFoundError:  # imported from a source tree that was never installed
    __version__ = "0+unknown"
