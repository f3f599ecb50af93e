"""Denoising renders with Intel Open Image Denoise (gi._core.Denoiser, renderer/denoiser.h).

OIDN is optional: it is loaded when denoising is asked for, from $GI_OIDN_LIBRARY, else the installed
pyoidn package's copy (`pip install pyoidn`; found without importing pyoidn), else the copy found
when the renderer was built, else the system's. Without it, asking to denoise raises DenoiserMissing
with what to install; nothing else changes."""
from __future__ import annotations

import importlib.util
import time
from pathlib import Path

import numpy as np

from .errors import DenoiserMissing


def pyoidn_library_folders():
    """[pyoidn's folder holding libOpenImageDenoise.so.2] when pyoidn is installed, else []."""
    try:
        spec = importlib.util.find_spec("pyoidn")
    except (ImportError, ValueError):
        spec = None
    if spec is None or not spec.submodule_search_locations:
        return []
    folder = Path(spec.submodule_search_locations[0]) / "oidn" / "lib"
    return [str(folder)] if folder.is_dir() else []


def open_denoiser(threads=0):
    """A gi._core.Denoiser; DenoiserMissing (with what to install) when no OIDN 2.x loads."""
    from .render import require_core
    core = require_core()
    try:
        return core.Denoiser(pyoidn_library_folders(), threads)
    except core.DenoiserUnavailable as error:
        raise DenoiserMissing(str(error)) from None


def denoise_result(denoiser, result, prefilter_aux=True):
    """(denoised colour (H, W, 3) float32, seconds it took) of a render result, guided by its
    albedo and normal AOVs."""
    start = time.perf_counter()
    color = denoiser.denoise(np.asarray(result.color), np.asarray(result.albedo), np.asarray(result.normal),
                             prefilter_aux)
    return np.asarray(color), time.perf_counter() - start


def denoise_metadata(denoiser, seconds, prefilter_aux=True):
    """EXR attributes saying the colour was denoised, by what and how."""
    aux = "prefiltered albedo and normal (cleanAux)" if prefilter_aux else "albedo and normal as rendered"
    return {"gi:denoised": f"Open Image Denoise {denoiser.version} RT filter (hdr), {aux}",
            "gi:denoise_seconds": f"{seconds:.3f}"}
