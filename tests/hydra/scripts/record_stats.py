"""Runs under OpenUSD's own Python: renders SCENE with Gi through UsdImagingGL.Engine set up as
usdrecord's FrameRecorder sets it up (no GPU, scene camera, framing, no camera light), until
converged, and prints one JSON object: stage open time, the time of the first Render call (Hydra
sync), hdGi's render stats (scene build, first pixel) and the total wall time.
With EDIT = "light", every light's intensity is then doubled and the render repeated (a scene
rebuild in the same session); its stats are printed as "stats_after_edit". With EDIT = "move",
the stage's first mesh is moved three times, rendering after each; the stats after each move are
printed as "stats_after_moves" (with the mesh's path as "moved"). With EDIT = "hide", the first
mesh is hidden, then shown; with EDIT = "material", it is bound to another material, then to its
own again: the stats after each are printed as "stats_after_edits" (its path as "edited"). With
EDIT = "reselect", the path tracer renders, then INTEGRATOR again ("stats_after_reselect").
INTEGRATOR may carry parameters: auto:autoHorizon=1 sets gi:auto:autoHorizon to 1.
    record_stats.py SCENE WIDTH INTEGRATOR SAMPLES [SEED] [EDIT]"""
import json
import sys
import time

from pxr import CameraUtil, Gf, Usd, UsdGeom, UsdImagingGL, UsdRender, UsdShade

total = time.perf_counter()
scene, width, integrator, samples = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
seed = int(sys.argv[5]) if len(sys.argv) > 5 else 0
edit = sys.argv[6] if len(sys.argv) > 6 else ""
start = time.perf_counter()
stage = Usd.Stage.Open(scene)
open_seconds = time.perf_counter() - start

path = stage.GetMetadata("renderSettingsPrimPath") or ""
settings = UsdRender.Settings(stage.GetPrimAtPath(path)) if path else None
targets = settings.GetCameraRel().GetForwardedTargets() if settings else []
camera = UsdGeom.Camera(stage.GetPrimAtPath(targets[0])) if targets else next(
    UsdGeom.Camera(p) for p in stage.Traverse() if p.IsA(UsdGeom.Camera))
gf_camera = camera.GetCamera(Usd.TimeCode.Default())
height = max(1, int(width / gf_camera.aspectRatio))

parameters = UsdImagingGL.Engine.Parameters()
parameters.gpuEnabled = False
engine = UsdImagingGL.Engine(parameters)
if not engine.SetRendererPlugin("HdGiRendererPlugin"):
    sys.exit("the Gi renderer plugin did not load")
integrator, _, integrator_params = integrator.partition(":")
engine.SetRendererSetting("gi:integrator", integrator)
for assignment in filter(None, integrator_params.split(",")):
    name, _, value = assignment.partition("=")
    engine.SetRendererSetting(f"gi:{integrator}:{name}", float(value))
engine.SetRendererSetting("convergedSamplesPerPixel", samples)
engine.SetRendererSetting("gi:seed", seed)
engine.SetRendererAov("color")
engine.SetCameraPath(camera.GetPath())
engine.SetFraming(CameraUtil.Framing(Gf.Rect2i(Gf.Vec2i(0, 0), width, height)))
engine.SetRenderBufferSize(Gf.Vec2i(width, height))
params = UsdImagingGL.RenderParams()
params.frame = Usd.TimeCode.Default()
params.colorCorrectionMode = "disabled"



def render_until_converged():
    engine.Render(stage.GetPseudoRoot(), params)
    while not engine.IsConverged():
        time.sleep(0.01)
        engine.Render(stage.GetPseudoRoot(), params)
    return {k: v for k, v in dict(engine.GetRenderStats()).items()}


start = time.perf_counter()
engine.Render(stage.GetPseudoRoot(), params)
first_render_call = time.perf_counter() - start
stats = render_until_converged()
render_seconds = time.perf_counter() - start
report = {"scene": scene, "width": width, "height": height, "open_seconds": open_seconds,
          "sync_seconds": first_render_call, "render_seconds": render_seconds, "stats": stats}
if edit == "light":
    for prim in stage.Traverse():
        intensity = prim.GetAttribute("inputs:intensity")
        if intensity and intensity.HasAuthoredValue():
            intensity.Set(2 * intensity.Get())
    report["stats_after_edit"] = render_until_converged()
elif edit == "reselect":
    engine.SetRendererSetting("gi:integrator", "path")
    render_until_converged()
    engine.SetRendererSetting("gi:integrator", integrator)
    report["stats_after_reselect"] = render_until_converged()
elif edit == "move":
    mesh = next(p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh))
    translate = UsdGeom.Xformable(mesh).AddTranslateOp(opSuffix="benchEdit")
    report["moved"] = str(mesh.GetPath())
    report["stats_after_moves"] = []
    for step in range(1, 4):
        translate.Set(Gf.Vec3d(0, 0.01 * step, 0))
        report["stats_after_moves"].append(render_until_converged())
elif edit in ("hide", "material"):
    mesh = next(p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh))
    report["edited"] = str(mesh.GetPath())
    report["stats_after_edits"] = []
    if edit == "hide":
        steps = [lambda: UsdGeom.Imageable(mesh).MakeInvisible(), lambda: UsdGeom.Imageable(mesh).MakeVisible()]
    else:
        binding = UsdShade.MaterialBindingAPI.Apply(mesh)
        own = binding.ComputeBoundMaterial()[0]
        other = next(UsdShade.Material(p) for p in stage.Traverse()
                     if p.IsA(UsdShade.Material) and (not own or p.GetPath() != own.GetPath()))
        steps = [lambda: binding.Bind(other), lambda: binding.Bind(own) if own else binding.UnbindDirectBinding()]
    for step in steps:
        step()
        report["stats_after_edits"].append(render_until_converged())
report["wall_seconds"] = time.perf_counter() - total
print(json.dumps(report, default=str))
