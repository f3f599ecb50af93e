"""`gi reference`: an unbiased path-traced reference image, rendered progressively.

The reference is made of batches: independent renders of the path integrator, each with its own seed,
with the integrator's default light transport (spec section 6, which every technique shares). Batches
double in samples per pixel up to MAX_BATCH_SPP, then stay at that size so that long references keep
adding batches to the spread estimate. The image is the spp-weighted mean of the batches.

Stopping rule: batch k's image mean m_k has variance s^2 / n_k (n_k its spp), so s^2 is estimated
from the batches' weighted spread, s^2 = sum n_k (m_k - M)^2 / (K - 1), and the standard error of
the combined mean M = sum n_k m_k / N is sqrt(s^2 / N). Rendering stops once SE / M falls below the
target (after at least MIN_BATCHES batches) or when the time limit passes.

A sun seen only through glass (window panes) the path tracer finds only when a BSDF-sampled ray,
refracted by the glass, reaches its small disc: a heavy-tailed estimate that reads far below its
mean for hours while its batches agree (Sibenik: half the sun's light after 600 s), so the spread
above does not show it. With sun_by_photons, light transport's linearity in the lights splits the
reference: the batches render the stage with its distant lights deactivated, and the progressive
photon map (consistent: its radii shrink) renders those lights alone for as long again; the image
is their sum (README, "A reference per light").
"""
from __future__ import annotations

import datetime
import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import __version__

INTEGRATOR = "path"
FIRST_BATCH_SPP = 1
MAX_BATCH_SPP = 256
MIN_BATCHES = 4        # a spread from fewer batches is too noisy to stop on
ESTIMATE_BATCHES = 2   # always render this many, even past the time limit, so there is an estimate


# -- statistics over batches ---------------------------------------------------------------------

def weighted_standard_error(weighted_sum, weighted_square_sum, total_weight, batches):
    """(mean, standard error of the mean) of batch values x_k whose variances are s^2 / n_k.

    weighted_sum = sum n_k x_k, weighted_square_sum = sum n_k x_k^2, total_weight = N = sum n_k.
    Works on scalars and, elementwise, on arrays. The error is inf with fewer than two batches."""
    mean = weighted_sum / total_weight
    if batches < 2:
        return mean, np.full_like(np.asarray(mean, dtype=np.float64), np.inf)
    # sum n_k (x_k - M)^2 = sum n_k x_k^2 - N M^2; rounding can make it slightly negative.
    spread = np.maximum(weighted_square_sum - total_weight * mean ** 2, 0.0)
    variance_per_sample = spread / (batches - 1)
    return mean, np.sqrt(variance_per_sample / total_weight)


class BatchAccumulator:
    """Running spp-weighted sums of batch images: the combined image and its error estimates."""

    def __init__(self):
        self.samples = 0
        self.batches = 0
        self._sum = None          # sum n_k x_k, per pixel and channel (float64)
        self._square_sum = None   # sum n_k x_k^2
        self._mean_sum = 0.0      # sum n_k m_k, m_k = batch k's image mean
        self._mean_square_sum = 0.0

    def add(self, color, spp):
        x = np.asarray(color, dtype=np.float64)[..., :3]
        if self._sum is None:
            self._sum, self._square_sum = np.zeros_like(x), np.zeros_like(x)
        self._sum += spp * x
        self._square_sum += spp * x * x
        batch_mean = float(x.mean())
        self._mean_sum += spp * batch_mean
        self._mean_square_sum += spp * batch_mean * batch_mean
        self.samples += spp
        self.batches += 1

    def image(self):
        return (self._sum / self.samples).astype(np.float32)

    def relative_standard_error(self):
        """Standard error of the image mean over the image mean (the stopping criterion)."""
        mean, error = weighted_standard_error(self._mean_sum, self._mean_square_sum, self.samples, self.batches)
        return float(error / mean) if mean > 0 else float("inf")

    def pixel_relative_standard_error(self):
        """RMS over pixels and channels of each value's standard error, over the image mean.

        Not the stopping criterion; recorded because the image mean converges long before single
        pixels do on large images, and a user judging a reference wants to know both."""
        mean, error = weighted_standard_error(self._sum, self._square_sum, self.samples, self.batches)
        image_mean = float(mean.mean())
        if not np.isfinite(error).all() or image_mean <= 0:
            return float("inf")
        return float(np.sqrt(np.mean(error ** 2)) / image_mean)

    def srgb8_standard_error(self):
        """The image's own noise on the 0-255 sRGB scale of gi.metrics.rmse_srgb8: RMS over pixels and
        channels of each value's standard error carried through the display encoding (a central
        difference of the clamped sRGB curve over +-1 standard error). An image scored against this
        reference has RMSE^2 ~ its own error^2 + this^2, so this is the floor the reference puts
        under every RMSE it measures."""
        from .metrics import srgb_encode
        mean, error = weighted_standard_error(self._sum, self._square_sum, self.samples, self.batches)
        if not np.isfinite(error).all():
            return float("inf")
        spread = srgb_encode(mean + error) - srgb_encode(mean - error)
        return float(255.0 * np.sqrt(np.mean((spread / 2.0) ** 2)))


def batch_seeds(seed):
    """Independent sampler seeds for successive batches, derived from the user's seed.

    SeedSequence keeps references made with different --seed values from sharing batches."""
    sequence = np.random.SeedSequence(seed)
    while True:
        for state in sequence.generate_state(64, dtype=np.uint32):
            yield int(state) & 0x7FFFFFFF  # RenderSettings.seed is a C int
        sequence = sequence.spawn(1)[0]


# -- rendering -----------------------------------------------------------------------------------

SUN_INTEGRATOR = "progressivePhotonMap"


def stage_with_suns(scene_path, keep):
    """(the stage of scene_path with either only its distant lights (keep=True) or everything but
    them active, edited in its session layer; how many distant lights it has)."""
    from pxr import UsdLux
    from .loader import open_stage
    stage = open_stage(Path(scene_path), False)
    stage.SetEditTarget(stage.GetSessionLayer())
    suns = 0
    for prim in stage.Traverse():
        if not prim.HasAPI(UsdLux.LightAPI) or prim.IsA(UsdLux.PortalLight):
            continue
        is_sun = prim.IsA(UsdLux.DistantLight)
        suns += is_sun
        if is_sun != keep:
            prim.SetActive(False)
    return stage, suns


@dataclass
class Reference:
    color: np.ndarray           # (H, W, 3) linear RGB
    spp: int
    batches: int
    seconds: float
    relative_standard_error: float
    pixel_relative_standard_error: float
    srgb8_standard_error: float  # the image's noise in 8-bit sRGB codes (BatchAccumulator.srgb8_standard_error)
    stopped_by: str             # 'target' | 'time'
    camera_path: str
    non_finite_samples: int     # samples the renderer replaced (NaN, Inf, negative), all batches
    sun: str = ""               # with sun_by_photons: how the distant lights' part was rendered


class ReferenceProgress:
    """A tqdm bar that moves with elapsed time or with the error's approach to the target."""

    def __init__(self, enabled, max_seconds, target_error):
        from .render import progress_bar
        self.bar, self._update = progress_bar("reference", enabled)
        self.max_seconds, self.target_error = max_seconds, target_error
        self.start = time.perf_counter()
        self.error_fraction = 0.0

    def elapsed(self):
        return time.perf_counter() - self.start

    def time_left(self):
        return self.max_seconds - self.elapsed() if self.max_seconds > 0 else float("inf")

    def tick(self, _fraction_of_batch=None):
        time_fraction = self.elapsed() / self.max_seconds if self.max_seconds > 0 else 0.0
        self._update(max(time_fraction, self.error_fraction))

    def batch_done(self, accumulator):
        error = accumulator.relative_standard_error()
        # The error falls as 1/sqrt(spp): (target / error)^2 is the fraction of samples taken so far.
        self.error_fraction = min((self.target_error / error) ** 2, 1.0) if error > 0 else 1.0
        self.bar.set_description(f"reference {accumulator.samples} spp, error {error:.2%}")
        self.tick()

    def close(self):
        self.bar.close()


def render_batch(loaded, spp, seed, threads, time_limit, resolution, progress):
    from .render import render_settings, require_core
    settings = render_settings(loaded, INTEGRATOR, {}, spp, seed, threads, time_limit, resolution, "box")
    return require_core().render(loaded.scene, settings, progress.tick)


def stop_reason(accumulator, target_error, progress):
    if accumulator.batches < ESTIMATE_BATCHES:
        return None
    if accumulator.batches >= MIN_BATCHES and accumulator.relative_standard_error() <= target_error:
        return "target"
    if progress.time_left() <= 0:
        return "time"
    return None


def render_reference(scene_path, max_seconds=3600.0, target_error=0.002, resolution=None, seed=0,
                     threads=0, camera=None, show_progress=False, sun_by_photons=False) -> Reference:
    """Renders batches until the image mean's relative standard error is under target_error or
    max_seconds (0 = no limit) have passed. With sun_by_photons (and a distant light), the batches
    leave the distant lights out, get half of max_seconds, and the photon map renders those lights
    alone for as long as the batches took (module docstring)."""
    from .loader import load_stage
    stage, suns = stage_with_suns(scene_path, keep=False) if sun_by_photons else (None, 0)
    loaded = load_stage(scene_path, camera=camera, stage=stage)
    if suns and max_seconds > 0:
        max_seconds /= 2
    accumulator = BatchAccumulator()
    progress = ReferenceProgress(show_progress, max_seconds, target_error)
    batch_spp, reason, non_finite = FIRST_BATCH_SPP, None, 0
    try:
        for seed_k in batch_seeds(seed):
            # A batch may be cut short by the time limit; its spp is then what it took, which
            # keeps it an unbiased batch (the cut does not depend on the samples' values).
            time_limit = max(progress.time_left(), 1e-6) if max_seconds > 0 else 0.0
            result = render_batch(loaded, batch_spp, seed_k, threads, time_limit, resolution, progress)
            non_finite += int(result.stats["non_finite_samples"])
            if result.spp > 0:
                accumulator.add(result.color, result.spp)
                progress.batch_done(accumulator)
            reason = stop_reason(accumulator, target_error, progress)
            if reason:
                break
            batch_spp = min(batch_spp * 2, MAX_BATCH_SPP)
    finally:
        progress.close()
    image, seconds, sun = accumulator.image(), progress.elapsed(), ""
    if suns:
        from .render import render_settings, require_core
        sun_loaded = load_stage(scene_path, camera=camera, stage=stage_with_suns(scene_path, keep=True)[0])
        settings = render_settings(sun_loaded, SUN_INTEGRATOR, {}, 1 << 24, seed, threads, max(seconds, 1.0),
                                   resolution, "box")
        start = time.perf_counter()
        result = require_core().render(sun_loaded.scene, settings)
        sun_seconds = time.perf_counter() - start
        non_finite += int(result.stats["non_finite_samples"])
        image = image + np.asarray(result.color, dtype=np.float32)[..., :3]
        seconds += sun_seconds
        sun = f"{SUN_INTEGRATOR} of the {suns} distant light(s) alone, {result.spp} spp in {sun_seconds:.1f} s"
    return Reference(image, accumulator.samples, accumulator.batches, seconds,
                     accumulator.relative_standard_error(), accumulator.pixel_relative_standard_error(),
                     accumulator.srgb8_standard_error(), reason, loaded.camera_path, non_finite, sun)


# -- the command ---------------------------------------------------------------------------------

def reference_metadata(scene, reference, seed, target_error, max_seconds):
    return {"gi:version": __version__, "gi:scene": str(scene), "gi:camera": reference.camera_path,
            "gi:integrator": INTEGRATOR, "gi:params": json.dumps({}), "gi:reference": "1",
            "gi:spp": str(reference.spp), "gi:seed": str(seed), "gi:batches": str(reference.batches),
            "gi:seconds": f"{reference.seconds:.3f}",
            "gi:relative_standard_error": f"{reference.relative_standard_error:.6g}",
            "gi:pixel_relative_standard_error": f"{reference.pixel_relative_standard_error:.6g}",
            "gi:srgb8_standard_error": f"{reference.srgb8_standard_error:.6g}",
            "gi:target_error": f"{target_error:g}", "gi:max_seconds": f"{max_seconds:g}",
            "gi:stopped_by": reference.stopped_by, "gi:non_finite_samples": str(reference.non_finite_samples),
            **({"gi:sun": reference.sun} if reference.sun else {}),
            "gi:date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")}


def make_reference(scene, output, max_seconds, target_error, resolution=None, seed=0, threads=0, camera=None,
                   show_progress=False, sun_by_photons=False):
    """Renders a reference (render_reference) and writes it with its metadata to `output`; returns it."""
    from .render import require_core
    if target_error <= 0:
        raise ValueError(f"--target-error must be positive, got {target_error}")
    reference = render_reference(scene, max_seconds, target_error, tuple(resolution) if resolution else None,
                                 seed, threads, camera, show_progress, sun_by_photons)
    output = Path(output)
    output.parent.mkdir(parents=True, exist_ok=True)
    require_core().write_rgb_exr(str(output), reference.color,
                                 reference_metadata(scene, reference, seed, target_error, max_seconds))
    return reference


def cmd_reference(args):
    reference = make_reference(args.scene, args.output, args.max_seconds, args.target_error, args.resolution,
                               args.seed, args.threads, args.camera, show_progress=sys.stderr.isatty(),
                               sun_by_photons=args.sun_by_photons)
    print(f"{args.scene}: {summary(reference, args.target_error)} -> {args.output}")
    return 0


def summary(reference, target_error):
    """One line: size, spp, batches, time, error estimate and why it stopped."""
    height, width = reference.color.shape[:2]
    outcome = "target reached" if reference.stopped_by == "target" else "time limit"
    return (f"{width}x{height} reference, {reference.spp} spp in {reference.batches} batches, "
            f"{reference.seconds:.2f} s; relative standard error of the mean "
            f"{reference.relative_standard_error:.4g} (target {target_error:g}, {outcome}), "
            f"its noise {reference.srgb8_standard_error:.2f} sRGB8 codes"
            + (f"; the sun by {reference.sun}" if reference.sun else ""))
