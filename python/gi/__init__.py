"""hdGi's Python front end: load USD stages into the renderer (gi.load_stage), render them
(`gi render`, gi._core.render) and inspect them (`gi inspect`)."""
from .errors import SceneError

__version__ = "0.1.0"
__all__ = ["load_stage", "LoadedScene", "SceneError", "__version__"]


def __getattr__(name):
    # The loader imports pxr, which is slow to import: load it on first use, not on `import gi`.
    if name in ("load_stage", "LoadedScene"):
        from . import loader
        return getattr(loader, name)
    raise AttributeError(f"module 'gi' has no attribute {name!r}")
