"""mimic: learn humanoid robot motions as neural networks and prove them in MuJoCo."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("mimic")
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0.0.0+local"

__all__ = ["__version__"]
