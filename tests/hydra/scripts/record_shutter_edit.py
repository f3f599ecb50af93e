"""Runs under OpenUSD's own Python: renders a motion-blur stage with Gi through one FrameRecorder
(one Hydra render index) while changing the camera's shutter between frames, so every rprim must
sample its motion again over the new interval. Writes <out>/<step>.exr.
Usage: record_shutter_edit.py STAGE OUT FRAME WIDTH OPEN:CLOSE... (one frame per shutter, in order)."""
import sys
from pathlib import Path

from pxr import Usd, UsdAppUtils, UsdGeom

scene, out, frame, width, shutters = sys.argv[1], Path(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]), sys.argv[5:]
out.mkdir(parents=True, exist_ok=True)
stage = Usd.Stage.Open(scene)
recorder = UsdAppUtils.FrameRecorder("HdGiRendererPlugin", False)
recorder.SetImageWidth(width)
recorder.SetCameraLightEnabled(False)
recorder.SetDomeLightVisibility(True)
recorder.SetColorCorrectionMode("disabled")
camera = UsdGeom.Camera(stage.GetPrimAtPath("/Camera"))
for step, shutter in enumerate(shutters):
    open_, close = (float(v) for v in shutter.split(":"))
    camera.GetShutterOpenAttr().Set(open_)
    camera.GetShutterCloseAttr().Set(close)
    recorder.Record(stage, camera, Usd.TimeCode(frame), str(out / f"{step}.exr"))
