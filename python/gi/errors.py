"""Errors the gi front end reports to users."""


class SceneError(Exception):
    """A scene file could not be loaded; the message names the file (and the prim if any)."""
