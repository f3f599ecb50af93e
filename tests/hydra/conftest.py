"""Hydra tests run OpenUSD's own tools (usdrecord, and scripts on its engine) in child
processes with the OpenUSD build's Python and `pxr`; this process keeps the venv's usd-core,
so the two `pxr` builds never meet in one interpreter."""

from pathlib import Path

import numpy as np
import pytest

from openusd import OPENUSD, PLUGIN, REPO, available, openusd_env, openusd_python, run_openusd  # noqa: F401

CORNELL = REPO / "scenes/cornell/cornell.usda"

if not available():
    pytest.skip(f"no OpenUSD build at {OPENUSD} or no hdGi plugin at {PLUGIN}", allow_module_level=True)


def hdgi_errors(text):
    """Python tracebacks, coding/runtime errors raised by hdGi (other OpenUSD components'
    own diagnostics, e.g. hgiGL's at window teardown, are not hdGi's), and hdGi's warning that
    the renderer replaced non-finite samples (renderSession.cpp): the film zeroes them, so an
    image's finite pixels alone do not show that none occurred."""
    return [line for line in text.splitlines()
            if "Traceback" in line
            or (("Coding Error" in line or "Runtime Error" in line) and ("hdGi" in line or "/hdGi/" in line))
            or ("hdGi" in line and "non-finite samples" in line)]


def read_rgb(path):
    from gi import _core
    pixels, _metadata = _core.read_image(str(path))
    image = np.asarray(pixels, dtype=np.float64)
    return image[..., :3]


def settings_layer(path, **settings):
    """A session layer setting gi:* attributes on the Cornell box's render settings prim."""
    lines = ["#usda 1.0", 'over "Render"', "{", '    over "Settings"', "    {"]
    for key, value in settings.items():
        kind = "string" if isinstance(value, str) else "float" if isinstance(value, float) else "int"
        literal = f'"{value}"' if isinstance(value, str) else repr(value)
        lines.append(f"        custom {kind} gi:{key.replace('__', ':')} = {literal}")
    lines += ["    }", "}", ""]
    Path(path).write_text("\n".join(lines))
    return path
