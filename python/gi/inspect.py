"""`gi inspect`: what a scene contains, as the loader sees it, and what rendering it needs:
textures (and their memory), subdivision meshes, specular and refractive surfaces that make
caustic paths, dome lights, instancing."""
from collections import Counter

from .descriptors import HAVE_CORE, CountingScene, new_scene
from .loader import load_stage

SMOOTH_ROUGHNESS = 0.1  # below this a specular lobe focuses light enough to make visible caustics


class AnalysingScene:
    """Wraps the scene the loader fills (the real one, or a CountingScene) and records each
    material and the triangles that use it."""

    def __init__(self, scene):
        self._scene = scene
        self.materials = {}                 # id -> descriptor
        self.triangles = Counter()          # material id -> triangles (spheres count as 0)
        self.spheres = Counter()            # material id -> spheres

    def add_material(self, material):
        material_id = self._scene.add_material(material)
        if material_id >= 0:
            self.materials[material_id] = material
        return material_id

    def add_mesh(self, name, positions, indices, normals=None, uvs=None, material=-1, *args, **kwargs):
        mesh_id = self._scene.add_mesh(name, positions, indices, normals, uvs, material, *args, **kwargs)
        if mesh_id >= 0:
            self.triangles[material] += len(indices)
        return mesh_id

    def add_sphere(self, name, center, radius, material=-1, *args, **kwargs):
        sphere_id = self._scene.add_sphere(name, center, radius, material, *args, **kwargs)
        if sphere_id >= 0:
            self.spheres[material] += 1
        return sphere_id

    def __getattr__(self, name):
        return getattr(self._scene, name)


def has_texture(texture):
    return bool(getattr(texture, "file", ""))


def caustic_kind(desc):
    """'refractive', 'mirror' or None: whether a material makes (sharp) caustic paths."""
    if desc.opacity_mode == "transparent" and (desc.opacity < 1 or has_texture(desc.opacity_texture)):
        return "refractive"
    smooth = desc.roughness < SMOOTH_ROUGHNESS and not has_texture(desc.roughness_texture)
    if desc.use_specular_workflow:
        reflects = max(desc.specular_color) > 0 or has_texture(desc.specular_color_texture)
    else:
        reflects = desc.metallic > 0 or has_texture(desc.metallic_texture)
    if smooth and reflects:
        return "mirror"
    if desc.clearcoat > 0 and desc.clearcoat_roughness < SMOOTH_ROUGHNESS:
        return "mirror"
    return None


def stage_analysis(path):
    """Subdivision meshes and point instancers, read from the stage itself (both hosts render
    subdivision meshes as their control cage at the lowest complexity and refine them above it)."""
    from pxr import Usd, UsdGeom
    stage = Usd.Stage.Open(str(path))
    subdivision, subdivision_faces, point_instancers, instanceable = [], 0, 0, 0
    for prim in stage.Traverse(Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)):
        if prim.IsA(UsdGeom.Mesh):
            mesh = UsdGeom.Mesh(prim)
            if mesh.GetSubdivisionSchemeAttr().Get() != UsdGeom.Tokens.none:
                subdivision.append(str(prim.GetPath()))
                subdivision_faces += len(mesh.GetFaceVertexCountsAttr().Get() or [])
        elif prim.IsA(UsdGeom.PointInstancer):
            point_instancers += 1
        if prim.IsInstance():
            instanceable += 1
    return {"subdivision_meshes": subdivision, "subdivision_faces": subdivision_faces,
            "point_instancers": point_instancers, "instanceable_prims": instanceable}


def inspect_scene(path):
    """Loads `path` (into the real renderer when it is built, for its statistics) and reports."""
    scene = AnalysingScene(new_scene() if HAVE_CORE else CountingScene())
    loaded = load_stage(path, scene)
    loaded.scene.commit()
    stats = loaded.scene.stats()
    specular = stats.get("specular_surfaces")
    caustics = []
    for material_id, desc in sorted(scene.materials.items()):
        kind = caustic_kind(desc)
        used = scene.triangles[material_id] + scene.spheres[material_id]
        if kind and used:
            caustics.append({"material": desc.name, "kind": kind, "triangles": scene.triangles[material_id],
                             "spheres": scene.spheres[material_id]})
    analysis = stage_analysis(path)
    return {
        "file": str(path),
        "prims": loaded.prims,
        "counts": loaded.counts,
        "lights": loaded.light_kinds,
        "textures": loaded.textures,
        "texture_bytes": stats.get("texture_bytes"),
        "camera": loaded.camera_path,
        "resolution": loaded.resolution,
        "caustic_paths": bool(caustics) if specular is None else bool(specular),
        "caustic_surfaces": caustics,
        "dome_lights": loaded.light_kinds.get("dome", 0),
        "instancing": loaded.counts.get("instances", 0) > 0,
        "moving": loaded.moving,
        "shutter": None if loaded.shutter is None else (loaded.shutter.open, loaded.shutter.close),
        **analysis,
        "build_seconds": stats.get("build_seconds"),
        "warnings": loaded.warnings + list(loaded.scene.warnings()),
    }


def yes_no(value):
    return "unknown (gi._core not built)" if value is None else ("yes" if value else "no")


def mebibytes(value):
    return "unknown (gi._core not built)" if value is None else f"{value / 2**20:.1f} MiB"


def format_report(report):
    counts = report["counts"]
    lights = ", ".join(f"{n} {kind}" for kind, n in sorted(report["lights"].items())) or "none"
    missing = sum(resolved is None for resolved in report["textures"].values())
    lines = [
        f"{report['file']}: {report['prims']} prims, {counts['meshes']} meshes, {counts['triangles']} triangles, "
        f"{counts['spheres']} exact spheres, {counts['materials']} materials",
        f"  camera: {report['camera'] or '(none: framing the scene from +Z)'} at "
        f"{report['resolution'][0]}x{report['resolution'][1]}",
        f"  lights: {lights}",
        f"  instances: {counts['instances']} of {counts['prototypes']} prototypes",
        f"  textures: {len(report['textures'])} ({missing} missing), {mebibytes(report['texture_bytes'])} in memory",
    ]
    for asset, resolved in sorted(report["textures"].items()):
        lines.append(f"    {asset}: {resolved or 'MISSING'}")
    subdivision = report["subdivision_meshes"]
    dome = report["dome_lights"]
    lines.append(f"  needs: textures {yes_no(bool(report['textures']))}")
    lines.append(f"  needs: subdivision {yes_no(bool(subdivision))}"
                 + (f" ({len(subdivision)} meshes, {report['subdivision_faces']} control faces; refined by "
                    f"`gi render --complexity` and by the host's complexity in Hydra, the cage at low)" if subdivision else ""))
    for path in subdivision[:10]:
        lines.append(f"      {path}")
    if len(subdivision) > 10:
        lines.append(f"      ... and {len(subdivision) - 10} more")
    lines.append(f"  needs: caustic paths {yes_no(report['caustic_paths'])}"
                 + (" (specular or refractive surfaces:)" if report["caustic_surfaces"] else ""))
    for surface in report["caustic_surfaces"]:
        used = f"{surface['triangles']} triangles" + (f", {surface['spheres']} spheres" if surface["spheres"] else "")
        lines.append(f"      {surface['kind']}: {surface['material']} ({used})")
    lines.append(f"  needs: dome light {yes_no(bool(dome))}" + (f" ({dome})" if dome else ""))
    lines.append(f"  needs: instancing {yes_no(report['instancing'])} ({counts['instances']} instances, "
                 f"{report['point_instancers']} point instancers, {report['instanceable_prims']} instanceable prims)")
    moving = report.get("moving") or {}
    if moving:  # nothing about motion when nothing moves
        opens, closes = report["shutter"]
        lines.append(f"  motion blur: {len(moving)} moving prims over the shutter, time codes {opens:g} to {closes:g}")
        for path, kinds in sorted(moving.items())[:10]:
            lines.append(f"      {path} ({', '.join(kinds)})")
        if len(moving) > 10:
            lines.append(f"      ... and {len(moving) - 10} more")
    if report.get("build_seconds") is not None:
        lines.append(f"  BVH build: {report['build_seconds']:.3f} s")
    lines += [f"  warning: {message}" for message in report["warnings"]]
    return "\n".join(lines)
