"""Errors the gi front end reports to users."""
import sys


class SceneError(Exception):
    """A scene file could not be loaded; the message names the file (and the prim if any)."""


class DenoiserMissing(Exception):
    """Denoising was asked for but Open Image Denoise 2.x is not installed; the message says what to install."""


def warn(message):
    print(f"gi: warning: {message}", file=sys.stderr)
