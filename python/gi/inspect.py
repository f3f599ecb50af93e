"""`gi inspect`: what a scene contains and what rendering it needs."""
import os
from collections import Counter

from pxr import Sdf, Usd, UsdGeom, UsdShade

from .lights import LIGHT_KINDS
from .loader import load_stage, open_stage


def inspect_scene(path):
    stage = open_stage(str(path))
    types = Counter(p.GetTypeName() or "(typeless)" for p in stage.Traverse())
    textures, subdivision = {}, 0
    for prim in stage.Traverse():
        if prim.IsA(UsdGeom.Mesh):
            scheme = UsdGeom.Mesh(prim).GetSubdivisionSchemeAttr().Get()
            subdivision += scheme not in (None, UsdGeom.Tokens.none)
        if prim.IsA(UsdShade.Shader) and UsdShade.Shader(prim).GetIdAttr().Get() == "UsdUVTexture":
            asset = UsdShade.Shader(prim).GetInput("file").Get() if UsdShade.Shader(prim).GetInput("file") else None
            if isinstance(asset, Sdf.AssetPath) and asset.path:
                resolved = asset.resolvedPath
                textures[asset.path] = resolved if resolved and os.path.isfile(resolved) else None
    loaded = load_stage(path)
    loaded.scene.commit()
    stats = loaded.scene.stats()
    return {
        "file": str(path),
        "prims": sum(types.values()),
        "types": dict(types),
        "lights": {kind: types.get(t, 0) for t, kind in LIGHT_KINDS.items() if types.get(t, 0)},
        "counts": loaded.counts,
        "triangles": int(stats["triangles"]),
        "subdivision_meshes": subdivision,
        "textures": textures,
        "texture_bytes": int(stats["texture_bytes"]),
        "specular_surfaces": bool(stats["specular_surfaces"]),
        "dome_lights": types.get("DomeLight", 0) + types.get("DomeLight_1", 0),
        "instances": loaded.counts["instances"],
        "camera": loaded.camera_path,
        "resolution": loaded.resolution,
        "warnings": loaded.warnings + loaded.scene.warnings(),
    }


def format_report(r):
    lines = [f"{r['file']}: {r['prims']} prims, {r['triangles']} triangles, "
             f"{r['counts']['spheres']} exact spheres, {r['counts']['meshes']} meshes, "
             f"{r['counts']['materials']} materials",
             f"  camera {r['camera'] or '(none)'} at {r['resolution'][0]}x{r['resolution'][1]}",
             f"  lights: " + (", ".join(f"{n} {k}" for k, n in r["lights"].items()) or "none"),
             f"  instances: {r['instances']} of {r['counts']['prototypes']} prototypes",
             f"  needs: caustic paths {'yes' if r['specular_surfaces'] else 'no'}, "
             f"subdivision {r['subdivision_meshes']} meshes, dome light {'yes' if r['dome_lights'] else 'no'}, "
             f"textures {len(r['textures'])} ({r['texture_bytes'] / 2**20:.1f} MiB loaded)"]
    for asset, resolved in sorted(r["textures"].items()):
        lines.append(f"    texture {asset}: {resolved or 'MISSING'}")
    for w in r["warnings"]:
        lines.append(f"  warning: {w}")
    return "\n".join(lines)
