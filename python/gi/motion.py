"""Motion blur in the USD loader: the camera's shutter interval, and the time codes within it at
which a moving prim is sampled for the renderer's motion geometry (gi._core's motion_points and
motion_transforms: evenly spaced steps, the first at shutter open, the last at shutter close).

The renderer interpolates linearly between steps, as USD interpolates between time samples, so
steps that include every authored sample inside the shutter reproduce USD's motion exactly: the
grid is the shutter's endpoints plus its authored samples when those are evenly spaced, else the
evenly spaced grid fine enough for the closest two of them (at most MAX_STEPS)."""
import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
from pxr import Gf, Usd, UsdGeom

MAX_STEPS = 64  # the renderer's kMaxMotionSteps


@dataclass(frozen=True)
class Shutter:
    """The time codes [open, close] the camera's shutter spans (frame + shutter:open/close)."""
    open: float
    close: float

    def interval(self):
        return Gf.Interval(self.open, self.close)


def frame_time(stage, time) -> float:
    """The frame number the shutter opens and closes around: `time`'s, or for the earliest time (a
    render without frames) the stage's start time code."""
    if time.IsEarliestTime() or time.IsDefault():
        return float(stage.GetStartTimeCode())
    return float(time.GetValue())


def camera_shutter(camera, settings, time, frame) -> Optional[Shutter]:
    """The shutter interval of `camera` (a UsdGeom.Camera prim) around `frame`, its attributes read
    at `time`; None when every ray sees one instant: no interval (close <= open: the renderer warns
    about close < open, naming the camera), or the render settings' disableMotionBlur or
    instantaneousShutter."""
    if settings is not None:
        for attribute in (settings.GetDisableMotionBlurAttr(), settings.GetInstantaneousShutterAttr()):
            if attribute and attribute.Get(time):
                return None
    schema = UsdGeom.Camera(camera)
    opening, closing = schema.GetShutterOpenAttr().Get(time), schema.GetShutterCloseAttr().Get(time)
    if opening is None or closing is None or not closing > opening:
        return None
    return Shutter(frame + float(opening), frame + float(closing))


def step_times(shutter: Shutter, sample_times) -> list:
    """Evenly spaced times from shutter open to close that include `sample_times` (those inside the
    shutter) when they are evenly spaced, and are at least as fine as their closest pair otherwise."""
    inside = sorted({float(t) for t in sample_times if shutter.open < t < shutter.close})
    times = [shutter.open, *inside, shutter.close]
    span = shutter.close - shutter.open
    closest = min(b - a for a, b in zip(times, times[1:]))
    segments = min(MAX_STEPS - 1, max(1, math.ceil(span / closest - 1e-9)))
    return [shutter.open + span * i / segments for i in range(segments + 1)]


def xform_sample_times(prim, shutter: Shutter) -> list:
    """The authored transform samples of `prim` and its ancestors inside the shutter; None when no
    transform among them can change over time."""
    times, varying = [], False
    while prim and not prim.IsPseudoRoot():
        xformable = UsdGeom.Xformable(prim)
        if xformable and xformable.TransformMightBeTimeVarying():
            varying = True
            times += xformable.GetTimeSamplesInInterval(shutter.interval())
        prim = prim.GetParent()
    return times if varying else None


def attribute_sample_times(attributes, shutter: Shutter) -> list:
    """The samples of `attributes` inside the shutter; None when none of them can change over time."""
    varying = [a for a in attributes if a and a.ValueMightBeTimeVarying()]
    if not varying:
        return None
    return [t for a in varying for t in a.GetTimeSamplesInInterval(shutter.interval())]


def camera_transforms(camera, shutter: Optional[Shutter]):
    """(steps, 4, 4) camera-to-world transforms of a moving camera prim over the shutter, or None."""
    times = xform_sample_times(camera, shutter) if shutter is not None else None
    if times is None:
        return None
    steps = np.stack([np.array(UsdGeom.XformCache(Usd.TimeCode(t)).GetLocalToWorldTransform(camera), np.float64)
                      for t in step_times(shutter, times)])
    return steps if moving(steps) else None


def moving(steps) -> bool:
    """Whether the per-step arrays differ (the renderer builds motion geometry only then)."""
    return any(not np.array_equal(steps[0], step) for step in steps[1:])


class MotionSampling:
    """What the USD loader (loader.StageLoader) does for motion blur: the step times of a prim's
    motion over `self.shutter` (None: no blur), its transforms, points and instance transforms at
    them, and `self.moving` (prim path -> what moves) for `gi inspect`. Uses the loader's
    `self.step_xforms` (time -> XformCache), `self.time` and `self.warn`."""

    def motion_times(self, prim, attributes=(), xform=True, moves=False):
        """The step times of `prim`'s motion over the shutter (its transform's if `xform`, and
        `attributes`'), or None when nothing of it can move (unless `moves`: velocities move it)."""
        if self.shutter is None:
            return None
        xform_times = xform_sample_times(prim, self.shutter) if xform else None
        attribute_times = attribute_sample_times(attributes, self.shutter)
        if xform_times is None and attribute_times is None and not moves:
            return None
        return step_times(self.shutter, (xform_times or []) + (attribute_times or []))

    def world_at(self, prim, time):
        if time not in self.step_xforms:
            self.step_xforms[time] = UsdGeom.XformCache(Usd.TimeCode(time))
        return self.step_xforms[time].GetLocalToWorldTransform(prim)

    def transform_steps(self, prim, times):
        """(steps, 4, 4) world transforms of `prim` at `times`, or None if they do not change."""
        if not times:
            return None
        steps = np.stack([np.array(self.world_at(prim, t), np.float64) for t in times])
        return steps if moving(steps) else None

    def note_motion(self, prim, kind):
        kinds = self.moving.setdefault(str(prim.GetPath()), [])
        if kind not in kinds:
            kinds.append(kind)

    def mesh_motion(self, prim, prototype):
        """The times a mesh's points are read at over the shutter (None when they do not change)
        and its world transforms (steps, 4, 4) (None when it does not move). A prototype's meshes
        move with their instances (their transform relative to the prototype is taken as fixed),
        but may deform."""
        points = UsdGeom.Mesh(prim).GetPointsAttr() if prim.IsA(UsdGeom.Mesh) else None
        times = self.motion_times(prim, [points] if points is not None else [], xform=prototype < 0)
        if not times:
            return None, None
        deform_times = None
        if points is not None and points.ValueMightBeTimeVarying():
            steps = [np.asarray(points.Get(t) or [], np.float64).reshape(-1, 3) for t in times]
            if any(len(step) != len(steps[0]) for step in steps):
                self.warn(str(prim.GetPath()), f"the number of points changes during the shutter "
                                               f"({sorted({len(step) for step in steps})}); rendered without "
                                               f"deformation blur")
            elif moving(steps):
                deform_times = times
        transform_steps = self.transform_steps(prim, times) if prototype < 0 else None
        return deform_times, transform_steps

    def instancer_motion(self, instancer, count):
        """Each instance's transform relative to the instancer at each motion step (USD extrapolates
        velocities and angular velocities over the shutter), and the instancer's world transforms;
        (None, None) when nothing can move."""
        velocities = [instancer.GetVelocitiesAttr(), instancer.GetAngularVelocitiesAttr()]
        attributes = [instancer.GetPositionsAttr(), instancer.GetOrientationsAttr(), instancer.GetScalesAttr(),
                      *velocities]
        times = self.motion_times(instancer.GetPrim(), attributes,
                                  moves=any(a.HasAuthoredValue() for a in velocities))
        if not times:
            return None, None
        step_local = instancer.ComputeInstanceTransformsAtTimes(
            [Usd.TimeCode(t) for t in times], self.time, UsdGeom.PointInstancer.ExcludeProtoXform,
            UsdGeom.PointInstancer.IgnoreMask)
        if len(step_local) != len(times) or any(len(step) != count for step in step_local):
            self.warn(str(instancer.GetPath()), "instance transforms could not be computed over the shutter; "
                                                "rendered without motion blur")
            return None, None
        return step_local, [self.world_at(instancer.GetPrim(), t) for t in times]
