"""hdGi's Python front end: load USD stages into the renderer, render, compare."""
__version__ = "0.1.0"

from .errors import SceneError


def load_stage(*args, **kwargs):
    """See gi.loader.load_stage (imported lazily: it needs pxr and the compiled core)."""
    from .loader import load_stage as _load_stage
    return _load_stage(*args, **kwargs)
