"""Runs under OpenUSD's own Python: renders the Cornell box with Gi through one FrameRecorder
(one Hydra render index) while editing the stage between frames, so every frame after the
first exercises hdGi's incremental sync. Writes <out>/<step>.exr and <out>/steps.json."""
import json
import sys
import time
from pathlib import Path

from pxr import Gf, Sdf, Usd, UsdAppUtils, UsdGeom, UsdShade

scene, out, width, integrator, samples = sys.argv[1], Path(sys.argv[2]), int(sys.argv[3]), sys.argv[4], int(sys.argv[5])
auto_horizon = float(sys.argv[6]) if len(sys.argv) > 6 else None  # integrator auto: its gi:auto:autoHorizon
out.mkdir(parents=True, exist_ok=True)

stage = Usd.Stage.Open(scene)
settings = stage.GetPrimAtPath("/Render/Settings")
settings.CreateAttribute("gi:integrator", Sdf.ValueTypeNames.String, custom=True).Set(integrator)
settings.CreateAttribute("gi:samples", Sdf.ValueTypeNames.Int, custom=True).Set(samples)
if auto_horizon is not None:
    settings.CreateAttribute("gi:auto:autoHorizon", Sdf.ValueTypeNames.Float, custom=True).Set(auto_horizon)

recorder = UsdAppUtils.FrameRecorder("HdGiRendererPlugin", False)
recorder.SetActiveRenderSettingsPrimPath(Sdf.Path("/Render/Settings"))
recorder.SetImageWidth(width)
recorder.SetCameraLightEnabled(False)
recorder.SetColorCorrectionMode("disabled")
camera = UsdGeom.Camera(stage.GetPrimAtPath("/World/Camera"))
sphere = stage.GetPrimAtPath("/World/GlassSphere")
translate = sphere.GetAttribute("xformOp:translate")
original = translate.Get()
steps = []


def record(name):
    start = time.perf_counter()
    recorder.Record(stage, camera, Usd.TimeCode.Default(), str(out / f"{name}.exr"))
    steps.append({"name": name, "seconds": time.perf_counter() - start})


record("original")
translate.Set(original + Gf.Vec3d(0.5, 0.0, 0.3))
record("moved")
translate.Set(original)
record("moved_back")
stage.GetPrimAtPath("/World/BackWall").SetActive(False)
record("removed")
stage.GetPrimAtPath("/World/BackWall").SetActive(True)
record("readded")
surface = UsdShade.Shader(stage.GetPrimAtPath("/World/Looks/White/Surface"))
surface.GetInput("diffuseColor").Set(Gf.Vec3f(0.2, 0.8, 0.2))
record("recolored")
UsdGeom.Imageable(stage.GetPrimAtPath("/World/Light")).MakeInvisible()
record("light_hidden")
(out / "steps.json").write_text(json.dumps(steps))
