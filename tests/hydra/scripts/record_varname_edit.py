"""Runs under OpenUSD's own Python: renders a parity stage with Gi through one FrameRecorder (one
Hydra render index) while changing a UsdPrimvarReader_float2's varname between frames, so the
mesh must pick its texture coordinates again from the edited material. Writes <out>/<step>.exr.
Usage: record_varname_edit.py STAGE OUT READER_PATH NAME... (one frame per varname, in order)."""
import sys
from pathlib import Path

from pxr import Sdf, Usd, UsdAppUtils, UsdGeom

scene, out, reader_path, names = sys.argv[1], Path(sys.argv[2]), sys.argv[3], sys.argv[4:]
out.mkdir(parents=True, exist_ok=True)
stage = Usd.Stage.Open(scene)
settings = stage.GetPrimAtPath("/Render/Settings")
settings.CreateAttribute("gi:integrator", Sdf.ValueTypeNames.String, custom=True).Set("path")
settings.CreateAttribute("gi:samples", Sdf.ValueTypeNames.Int, custom=True).Set(4)

recorder = UsdAppUtils.FrameRecorder("HdGiRendererPlugin", False)
recorder.SetImageWidth(240)
recorder.SetCameraLightEnabled(False)
recorder.SetColorCorrectionMode("disabled")
camera = UsdGeom.Camera(stage.GetPrimAtPath("/World/Camera"))
varname = stage.GetPrimAtPath(reader_path).GetAttribute("inputs:varname")
for step, name in enumerate(names):
    varname.Set(name)
    recorder.Record(stage, camera, Usd.TimeCode.Default(), str(out / f"{step}-{name}.exr"))
