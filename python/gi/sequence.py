"""A stage rendered at several time codes in one process (`gi render --frames`).

The stage is opened once. The renderer's scene is immutable once built (its BVH is built at
commit), so each frame where something other than the camera moves is loaded anew from the open
stage, with the stage read at that frame's time code: transforms, points, cameras, lights and
material parameters. Its BVH is built only where something changed since the previous frame
(Scene.reuse_bvh_of): what stayed the same keeps the previous frame's, while frames are short
enough for that to pay (STATIC_BVH_TRACE_COST). When only the render camera moves (a
fly-through), the scene is built once and every frame renders it through that frame's camera. A
stage with nothing animated is built once for all frames."""
import time
from dataclasses import dataclass

from . import descriptors
from .frames import authored_time_range, format_frames, only_camera_moves
from .loader import camera_at, load_stage, open_stage


# What tracing through the kept static BVH costs, as a share of a frame's render time: it is
# instanced once in the frame's top level, and rays entering it cost Embree 11-15% more (measured
# with gi._core.embree_ray_benchmark, 1M incoherent rays, and with the render's own rays replayed,
# Sponza and Sibenik with a moving ball, one thread), the path tracer's render 5-12% more. Keeping
# BVHs pays while this share of the previous frame's render time is less than the whole scene's
# build time (the first frame's), i.e. for short frames (Sponza: under about 1.5 s); longer frames
# build one flat BVH as a frame rendered alone does.
STATIC_BVH_TRACE_COST = 0.08


@dataclass
class Frame:
    number: object          # the frame (an int), or None for the earliest time (no --frames)
    loaded: object          # the LoadedScene to render
    camera: object = None   # a CameraDesc overriding the scene's (camera-only animation), or None
    rebuilt: bool = True    # the scene was loaded for this frame (False: the previous frame's)


class Sequence:
    def __init__(self, scene_path, frames, camera=None, time_range_flag="--frames", allow_missing=False,
                 refine_level=0, purposes=None):
        """frames: frame numbers, or [None] for the earliest time; allow_missing, refine_level,
        purposes: as load_stage's."""
        self.path, self.frames, self.requested_camera = str(scene_path), list(frames), camera
        self.refine_level, self.purposes = refine_level, purposes
        self.stage = open_stage(self.path, allow_missing)
        self.warnings = []
        self.time_range = authored_time_range(self.stage)
        if self.frames != [None]:
            self.warnings += self.range_warnings(time_range_flag)
        self.reuse = None  # 'static' | 'camera' | None, decided on the first frame

    def range_warnings(self, flag):
        spec = format_frames(self.frames)
        if self.time_range is None:
            return [f"{flag} {spec}: {self.path} has no time samples; every frame renders the same "
                    f"scene (each with its own seed)"]
        low, high = self.time_range
        outside = [f for f in self.frames if f < low or f > high]
        if not outside:
            return []
        return [f"{flag} {spec}: frames {format_frames(outside)} are outside {self.path}'s time samples "
                f"({low:g} to {high:g}); there each attribute holds its nearest sample"]

    def __iter__(self):
        first = previous = None
        render_seconds = 0.0  # the previous frame's, from its yield to the next frame
        for number in self.frames:
            if first is None:
                first = load_stage(self.path, camera=self.requested_camera, time=number, stage=self.stage,
                                   refine_level=self.refine_level, purposes=self.purposes)
                if self.time_range is None:
                    self.reuse = "static"
                elif only_camera_moves(self.stage, first.camera_path):
                    self.reuse = "camera"
                start = time.perf_counter()
                yield Frame(number, first)
                render_seconds = time.perf_counter() - start
            elif self.reuse == "static":
                yield Frame(number, first, rebuilt=False)
            elif self.reuse == "camera":
                yield Frame(number, first, camera_at(self.stage, first.camera_path, number), rebuilt=False)
            else:
                # The previous frame's scene is committed (rendered) by now: its BVHs are offered.
                scene = descriptors.new_scene()
                if STATIC_BVH_TRACE_COST * render_seconds < first.scene.stats().get("build_seconds", 0):
                    scene.reuse_bvh_of((previous or first).scene)
                previous = load_stage(self.path, scene, camera=self.requested_camera, time=number,
                                      stage=self.stage, refine_level=self.refine_level, purposes=self.purposes)
                start = time.perf_counter()
                yield Frame(number, previous)
                render_seconds = time.perf_counter() - start
