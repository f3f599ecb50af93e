"""Frame ranges, per-frame output names and seeds, and what of a stage changes over time: what
`gi render --frames` and `gi job` share.

A frame range is Open Job Description's range expression (so a job's task parameter is one):
`1-48`, `1-48:2`, `7`, `1-10,20,30-40:5`, negative frames allowed (`-5--1`)."""
import re

from pxr import Usd, UsdGeom

from .lights import is_light

RANGE_PART = re.compile(r"^\s*(-?\d+)(?:\s*-\s*(-?\d+)(?:\s*:\s*(-?\d+))?)?\s*$")


def parse_frames(text):
    """The frames of a range expression, in order, each once; ValueError saying what is wrong."""
    frames = []
    for part in text.split(","):
        match = RANGE_PART.match(part)
        if not match:
            raise ValueError(f"{text!r}: {part.strip()!r} is not a frame, FIRST-LAST or FIRST-LAST:STEP")
        first, last, step = match.groups()
        first = int(first)
        last = int(last) if last is not None else first
        step = int(step) if step is not None else 1
        if step <= 0:
            raise ValueError(f"{text!r}: the step {step} must be positive")
        if last < first:
            raise ValueError(f"{text!r}: {part.strip()} ends before it starts")
        frames += [f for f in range(first, last + 1, step) if f not in frames]
    return frames


def format_frames(frames):
    """The shortest range expression of `frames` (ascending runs of one step)."""
    parts, i = [], 0
    while i < len(frames):
        j = i + 1
        step = frames[j] - frames[i] if j < len(frames) else 1
        while j < len(frames) and frames[j] - frames[j - 1] == step and step > 0:
            j += 1
        if j - i == 1:
            parts.append(str(frames[i]))
        elif j - i == 2 and step != 1:  # two frames: a list says it plainly
            parts += [str(frames[i]), str(frames[i + 1])]
        else:
            parts.append(f"{frames[i]}-{frames[j - 1]}" + (f":{step}" if step != 1 else ""))
        i = j
    return ",".join(parts)


def chunks(frames, size):
    """`frames` in consecutive chunks of at most `size` frames, each as a range expression."""
    return [format_frames(frames[i:i + size]) for i in range(0, len(frames), size)]


def has_frame_token(path):
    from .render import require_core
    return require_core().has_frame_token(str(path))


def frame_path(path, frame):
    """`path` with its frame tokens replaced by `frame`: `####` and `$F4` zero-padded to their
    width, `$F` not padded (renderer/render_vars.h: hdGi's render products follow it too)."""
    from .render import require_core
    return require_core().frame_path(str(path), int(frame))


def frame_seed(seed, frame):
    """The seed frame `frame` renders with: seed + frame (mod 2^32), hdGi's rule too
    (renderer/render_vars.h), so any frame renders alone the same as in a sequence, a farm chunk or
    usdrecord --frames."""
    from .render import require_core
    return require_core().frame_seed(int(seed) % (1 << 32), float(frame))


def authored_time_range(stage):
    """(earliest, latest) time sample of any attribute on the stage, or None when nothing is
    animated."""
    low = high = None
    for prim in stage.TraverseAll():
        for attribute in prim.GetAttributes():
            samples = attribute.GetTimeSamples()
            if samples:
                low = samples[0] if low is None else min(low, samples[0])
                high = samples[-1] if high is None else max(high, samples[-1])
    return None if low is None else (low, high)


def _varies(prim):
    return any(attribute.ValueMightBeTimeVarying() for attribute in prim.GetAttributes())


def _renders_something(prim):
    """Geometry, a light or an instance at or under `prim`."""
    return any(p.IsA(UsdGeom.Gprim) or p.IsA(UsdGeom.PointInstancer) or p.IsInstance() or is_light(p)
               for p in Usd.PrimRange(prim))


def only_camera_moves(stage, camera_path):
    """True when nothing but the camera `camera_path` varies over time: its own attributes, or
    transforms above it that carry nothing rendered. Then the scene built once renders every frame
    with the camera read per frame. False when anything else varies, or when there is no camera."""
    if not camera_path:
        return False
    camera = stage.GetPrimAtPath(camera_path)
    above = set()
    parent = camera.GetParent()
    while parent:
        above.add(parent.GetPath())
        parent = parent.GetParent()
    for prim in stage.TraverseAll():
        if not _varies(prim):
            continue
        if prim.GetPath() != camera.GetPath() and prim.GetPath() not in above:
            return False
        if _renders_something(prim):
            return False
    return True
