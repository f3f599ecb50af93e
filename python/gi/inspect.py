"""`gi inspect`: what a scene contains, as the loader sees it."""
from .descriptors import HAVE_CORE, CountingScene, new_scene
from .loader import load_stage


def inspect_scene(path):
    """Loads `path` (into the real renderer when it is built, for its statistics) and reports."""
    loaded = load_stage(path, new_scene() if HAVE_CORE else CountingScene())
    loaded.scene.commit()
    stats = loaded.scene.stats()
    specular = stats.get("specular_surfaces")
    return {
        "file": str(path),
        "prims": loaded.prims,
        "counts": loaded.counts,
        "lights": loaded.light_kinds,
        "textures": loaded.textures,
        "camera": loaded.camera_path,
        "resolution": loaded.resolution,
        "caustic_paths": None if specular is None else bool(specular),
        "warnings": loaded.warnings + list(loaded.scene.warnings()),
    }


def yes_no(value):
    return "unknown (gi._core not built)" if value is None else ("yes" if value else "no")


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
        f"  textures: {len(report['textures'])} ({missing} missing)",
    ]
    for asset, resolved in sorted(report["textures"].items()):
        lines.append(f"    {asset}: {resolved or 'MISSING'}")
    lines.append(f"  needs: caustic paths {yes_no(report['caustic_paths'])}")
    lines += [f"  warning: {message}" for message in report["warnings"]]
    return "\n".join(lines)
