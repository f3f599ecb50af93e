"""Loads a USD stage through the pxr Python API into a gi._core.Scene."""
import os
from dataclasses import dataclass, field

import numpy as np
from pxr import Sdf, Usd, UsdGeom, UsdRender, UsdShade

from . import _core
from .errors import SceneError
from .geometry import implicit_triangles, mesh_triangles
from .lights import LIGHT_KINDS, light_desc
from .materials import material_desc

IMPLICIT_TYPES = ("Cube", "Cylinder", "Cone", "Capsule", "Plane")


@dataclass
class LoadedScene:
    scene: object
    resolution: tuple
    camera_path: str
    warnings: list = field(default_factory=list)
    counts: dict = field(default_factory=dict)


def open_stage(path):
    if not os.path.exists(path):
        raise SceneError(f"{path}: no such file")
    try:
        stage = Usd.Stage.Open(str(path))
    except Exception as error:  # pxr raises Tf.ErrorException with the parser's message
        first = str(error).strip().splitlines()
        raise SceneError(f"{path}: not a readable USD file ({first[-1] if first else error})") from None
    if stage is None:
        raise SceneError(f"{path}: not a readable USD file")
    return stage


def _matrix(m):
    a = np.array(m, dtype=np.float64)
    return a if np.isfinite(a).all() else a  # the renderer rejects non-finite transforms with a warning


class _Loader:
    def __init__(self, stage, scene, time, path):
        self.stage, self.scene, self.time, self.path = stage, scene, time, path
        self.xforms = UsdGeom.XformCache(time)
        self.warnings = []
        self.materials = {}          # material prim path -> id
        self.display_colors = {}     # rgb tuple -> id
        self.prototypes = {}         # prototype prim path -> id
        self.counts = dict(meshes=0, triangles=0, spheres=0, lights=0, instances=0, materials=0,
                           prototypes=0)

    def warn(self, message):
        self.warnings.append(f"{self.path}: {message}")

    # -- materials ---------------------------------------------------------------------------
    def material_for(self, prim):
        material, _ = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial()
        if material:
            key = str(material.GetPath())
            if key not in self.materials:
                desc = material_desc(material, self.warn)
                self.materials[key] = self.scene.add_material(desc) if desc is not None else -1
                self.counts["materials"] += desc is not None
            return self.materials[key]
        primvar = UsdGeom.PrimvarsAPI(prim).GetPrimvar("displayColor")
        if primvar and primvar.HasValue():
            colors = primvar.ComputeFlattened(self.time)
            if colors is not None and len(colors):
                rgb = tuple(float(c) for c in colors[0])
                if rgb not in self.display_colors:
                    desc = _core.MaterialDesc()
                    desc.name = f"{prim.GetPath()} displayColor"
                    desc.diffuse_color = rgb
                    self.display_colors[rgb] = self.scene.add_material(desc)
                return self.display_colors[rgb]
        return -1

    # -- geometry ----------------------------------------------------------------------------
    def add_gprim(self, prim, transform, prototype=-1):
        name = str(prim.GetPath())
        material = self.material_for(prim)
        if prim.IsA(UsdGeom.Sphere):
            radius = UsdGeom.Sphere(prim).GetRadiusAttr().Get(self.time)
            if self.scene.add_sphere(name, (0.0, 0.0, 0.0), float(radius), material, transform,
                                     prototype) >= 0:
                self.counts["spheres"] += 1
            return
        if prim.IsA(UsdGeom.Mesh):
            tris = mesh_triangles(UsdGeom.Mesh(prim), self.time, self.warn)
            double_sided = bool(UsdGeom.Mesh(prim).GetDoubleSidedAttr().Get(self.time))
        elif prim.GetTypeName() in IMPLICIT_TYPES:
            tris = implicit_triangles(prim, self.time, self.warn)
            double_sided = True
        else:
            return
        if tris is None:
            return
        if self.scene.add_mesh(name, tris.positions, tris.indices, tris.normals, tris.uvs, material,
                               transform, double_sided, prototype) >= 0:
            self.counts["meshes"] += 1
            self.counts["triangles"] += len(tris.indices)

    def add_prototype(self, root, key):
        """Geometry under `root` once, in object space relative to root, as a prototype."""
        if key in self.prototypes:
            return self.prototypes[key]
        proto = self.scene.add_prototype(key)
        self.prototypes[key] = proto
        self.counts["prototypes"] += 1
        root_inverse = self.xforms.GetLocalToWorldTransform(root).GetInverse()
        for prim in Usd.PrimRange(root, Usd.TraverseInstanceProxies()):
            if not prim.IsA(UsdGeom.Gprim) or not self.visible(prim):
                continue
            local = self.xforms.GetLocalToWorldTransform(prim) * root_inverse
            self.add_gprim(prim, _matrix(local), proto)
        return proto

    def add_point_instancer(self, prim):
        instancer = UsdGeom.PointInstancer(prim)
        targets = instancer.GetPrototypesRel().GetTargets()
        protos = [self.add_prototype(self.stage.GetPrimAtPath(t), str(t)) for t in targets]
        transforms = instancer.ComputeInstanceTransformsAtTime(self.time, self.time)
        indices = instancer.GetProtoIndicesAttr().Get(self.time) or []
        mask = instancer.ComputeMaskAtTime(self.time)
        world = self.xforms.GetLocalToWorldTransform(prim)
        for i, (index, local) in enumerate(zip(indices, transforms or [])):
            if mask and not mask[i]:
                continue
            if not 0 <= index < len(protos):
                self.warn(f"point instancer {prim.GetPath()}: instance {i} names prototype {index} "
                          f"of {len(protos)}; skipped")
                continue
            if self.scene.add_instance(protos[index], _matrix(local * world), f"{prim.GetPath()}[{i}]") >= 0:
                self.counts["instances"] += 1

    def add_instanceable(self, prim):
        prototype = prim.GetPrototype()
        proto = self.add_prototype(prototype, str(prototype.GetPath()))
        world = self.xforms.GetLocalToWorldTransform(prim)
        if self.scene.add_instance(proto, _matrix(world), str(prim.GetPath())) >= 0:
            self.counts["instances"] += 1

    def visible(self, prim):
        imageable = UsdGeom.Imageable(prim)
        if imageable.ComputeVisibility(self.time) == UsdGeom.Tokens.invisible:
            return False
        return imageable.ComputePurpose() in (UsdGeom.Tokens.default_, UsdGeom.Tokens.render)

    def load(self):
        it = iter(Usd.PrimRange(self.stage.GetPseudoRoot()))
        for prim in it:
            if prim.IsA(UsdGeom.Imageable) and not self.visible(prim):
                it.PruneChildren()
                continue
            if prim.IsInstance():
                self.add_instanceable(prim)
                it.PruneChildren()
            elif prim.IsA(UsdGeom.PointInstancer):
                self.add_point_instancer(prim)
                it.PruneChildren()
            elif prim.GetTypeName() in LIGHT_KINDS:
                desc = light_desc(prim, self.xforms.GetLocalToWorldTransform(prim), self.warn)
                if desc is not None:
                    self.scene.add_light(desc)
                    self.counts["lights"] += 1
            elif prim.IsA(UsdGeom.Gprim):
                self.add_gprim(prim, _matrix(self.xforms.GetLocalToWorldTransform(prim)))


def _render_settings(stage):
    path = stage.GetMetadata("renderSettingsPrimPath")
    if path:
        prim = stage.GetPrimAtPath(path)
        if prim and prim.IsA(UsdRender.Settings):
            return UsdRender.Settings(prim)
    for prim in stage.Traverse():
        if prim.IsA(UsdRender.Settings):
            return UsdRender.Settings(prim)
    return None


def camera_desc(prim, xforms, time):
    cam = UsdGeom.Camera(prim)
    d = _core.CameraDesc()
    d.name = str(prim.GetPath())
    d.projection = str(cam.GetProjectionAttr().Get(time))
    d.focal_length = float(cam.GetFocalLengthAttr().Get(time))
    d.horizontal_aperture = float(cam.GetHorizontalApertureAttr().Get(time))
    d.vertical_aperture = float(cam.GetVerticalApertureAttr().Get(time))
    d.horizontal_aperture_offset = float(cam.GetHorizontalApertureOffsetAttr().Get(time))
    d.vertical_aperture_offset = float(cam.GetVerticalApertureOffsetAttr().Get(time))
    d.f_stop = float(cam.GetFStopAttr().Get(time))
    d.focus_distance = float(cam.GetFocusDistanceAttr().Get(time))
    near, far = cam.GetClippingRangeAttr().Get(time)
    d.clipping_range = (float(near), float(far))
    d.transform = np.array(xforms.GetLocalToWorldTransform(prim), dtype=np.float64)
    return d


def load_stage(path, scene=None, camera=None, time=Usd.TimeCode.Default()):
    """Loads `path` into `scene` (a new gi._core.Scene if None). `camera` is a prim path that
    overrides the render settings' camera. Raises SceneError naming the file."""
    stage = open_stage(str(path))
    scene = scene if scene is not None else _core.Scene()
    loader = _Loader(stage, scene, time, str(path))
    loader.load()

    settings = _render_settings(stage)
    resolution = (512, 512)
    camera_prim = None
    if settings is not None:
        res = settings.GetResolutionAttr().Get(time)
        if res is not None:
            resolution = (int(res[0]), int(res[1]))
        targets = settings.GetCameraRel().GetTargets()
        if targets:
            camera_prim = stage.GetPrimAtPath(targets[0])
    if camera is not None:
        camera_prim = stage.GetPrimAtPath(camera)
        if not camera_prim or not camera_prim.IsA(UsdGeom.Camera):
            raise SceneError(f"{path}: {camera} is not a camera prim")
    if camera_prim is None:
        camera_prim = next((p for p in stage.Traverse() if p.IsA(UsdGeom.Camera)), None)
    camera_path = ""
    if camera_prim is not None and camera_prim.IsA(UsdGeom.Camera):
        scene.set_camera(camera_desc(camera_prim, loader.xforms, time))
        camera_path = str(camera_prim.GetPath())
    else:
        loader.warn("no camera in the stage; using a view of the whole scene from +Z")
    return LoadedScene(scene, resolution, camera_path, loader.warnings, loader.counts)
