"""A stage rendered at several time codes in one process (`gi render --frames`).

The stage is opened once. The renderer's scene is immutable once built (its BVH is built at
commit), so each frame where something other than the camera moves is loaded anew from the open
stage, with the stage read at that frame's time code: transforms, points, cameras, lights and
material parameters. When only the render camera moves (a fly-through), the scene is built once
and every frame renders it through that frame's camera. A stage with nothing animated is built
once for all frames."""
from dataclasses import dataclass

from .frames import authored_time_range, format_frames, only_camera_moves
from .loader import camera_at, load_stage, open_stage


@dataclass
class Frame:
    number: object          # the frame (an int), or None for the earliest time (no --frames)
    loaded: object          # the LoadedScene to render
    camera: object = None   # a CameraDesc overriding the scene's (camera-only animation), or None
    rebuilt: bool = True    # the scene was loaded for this frame (False: the previous frame's)


class Sequence:
    def __init__(self, scene_path, frames, camera=None, time_range_flag="--frames", allow_missing=False,
                 refine_level=0):
        """frames: frame numbers, or [None] for the earliest time; allow_missing, refine_level: as
        load_stage's."""
        self.path, self.frames, self.requested_camera = str(scene_path), list(frames), camera
        self.refine_level = refine_level
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
        first = None
        for number in self.frames:
            if first is None:
                first = load_stage(self.path, camera=self.requested_camera, time=number, stage=self.stage,
                                   refine_level=self.refine_level)
                if self.time_range is None:
                    self.reuse = "static"
                elif only_camera_moves(self.stage, first.camera_path):
                    self.reuse = "camera"
                yield Frame(number, first)
            elif self.reuse == "static":
                yield Frame(number, first, rebuilt=False)
            elif self.reuse == "camera":
                yield Frame(number, first, camera_at(self.stage, first.camera_path, number), rebuilt=False)
            else:
                yield Frame(number, load_stage(self.path, camera=self.requested_camera, time=number,
                                               stage=self.stage, refine_level=self.refine_level))
