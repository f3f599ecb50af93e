"""gi's Python render API: render settings, a loaded scene rendered, a scene file rendered.

The commands (gi.cli, gi.render_command, gi.study, gi.reference), bench/ and the tests render
through these functions. gi._core is imported lazily, so `gi --help` and `gi inspect` work before
the renderer is built."""
import sys
from pathlib import Path


# usdrecord's --complexity and the refine level UsdImaging gives subdivision meshes for it
# (UsdImagingGLEngine's _GetRefineLevel of RefinementComplexities 1.0, 1.1, 1.2, 1.3); low, the
# control cage, is usdrecord's default (UsdAppUtils.complexityArgs) and UsdImagingGLRenderParams'.
COMPLEXITY_REFINE_LEVELS = {"low": 0, "medium": 1, "high": 2, "veryhigh": 3}
DEFAULT_COMPLEXITY = "low"


class CoreMissing(RuntimeError):
    """gi._core, the compiled renderer, is not built."""


def require_core():
    try:
        from . import _core
    except ImportError as error:
        raise CoreMissing(f"gi._core (the compiled renderer) is not available ({error}); "
                          f"build it with scripts/build.sh") from None
    return _core


def integrator_catalog():
    """gi._core.integrators(), or [] when the core is not built (`gi render` then says so)."""
    try:
        from . import _core
    except ImportError:
        return []
    return _core.integrators()


def preset_catalog():
    """gi._core.presets(), or [] when the core is not built."""
    try:
        from . import _core
    except ImportError:
        return []
    return _core.presets()


def progress_bar(description, enabled):
    """A tqdm bar and the progress(fraction) callback that moves it."""
    from tqdm import tqdm
    bar = tqdm(total=100, desc=description, disable=not enabled, leave=False, file=sys.stderr,
               bar_format="{desc}: {percentage:3.0f}%|{bar}| {elapsed}<{remaining}")

    def update(fraction):
        bar.n = min(max(fraction, 0.0), 1.0) * 100
        bar.refresh()
    return bar, update


def render_settings(loaded, integrator, params, spp, seed, threads, time_limit, resolution, pixel_filter):
    settings = require_core().RenderSettings()
    settings.width, settings.height = resolution or loaded.resolution
    settings.spp = spp
    settings.integrator = integrator
    settings.params = dict(params or {})
    settings.seed = seed
    settings.threads = threads
    settings.time_limit = time_limit
    if hasattr(settings, "filter"):  # not in _core.pyi's contract; set only where the core has it
        settings.filter = pixel_filter
    if loaded.framing is not None:
        settings.aspect_ratio_conform_policy, settings.pixel_aspect_ratio = loaded.framing
    return settings


def render_loaded(loaded, settings, label, show_progress=False, camera=None, progress=None):
    """Renders a loaded scene (through `camera` when given); progress(fraction) instead of a bar
    of its own when given."""
    bar, update = progress_bar(label, show_progress and progress is None)
    try:
        return require_core().render(loaded.scene, settings, progress or update, camera)
    finally:
        bar.close()


def render_scene(scene_path, integrator="path", params=None, spp=16, seed=0, threads=0, time_limit=0.0,
                 resolution=None, camera=None, show_progress=False, pixel_filter="box", refine_level=0):
    """Loads and renders a scene (subdivision meshes refined refine_level times); returns (result,
    loaded scene, settings)."""
    from .loader import load_stage
    loaded = load_stage(scene_path, camera=camera, refine_level=refine_level)
    settings = render_settings(loaded, integrator, params, spp, seed, threads, time_limit, resolution,
                               pixel_filter)
    result = render_loaded(loaded, settings, f"{Path(scene_path).name} [{integrator}]", show_progress)
    return result, loaded, settings
