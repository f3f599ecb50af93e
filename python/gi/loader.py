"""Loads a USD stage through the pxr Python API into a gi._core.Scene (or any object with the same
methods): geometry, instancing, materials, lights, camera and render settings.

Problems in the file never stop a load: they become warnings naming the file and the prim, and
the offending part is left out. Only a file that cannot be opened raises SceneError."""
import math
import os
import re
from collections import Counter
from dataclasses import dataclass, field

import numpy as np
from pxr import Gf, Usd, UsdGeom, UsdLux, UsdRender, UsdShade

from . import descriptors, motion
from .errors import SceneError
from .geometry import IMPLICIT_TYPES, implicit_triangles, mesh_triangles
from .lights import is_light, light_desc
from .materials import UNREADABLE, MaterialLibrary, error_text

DEFAULT_RESOLUTION = (512, 512)
# UsdRenderSettings' includedPurposes fallback: what a final frame shows when nothing says otherwise.
RENDERED_PURPOSES = (UsdGeom.Tokens.default_, UsdGeom.Tokens.render)
PURPOSES = (UsdGeom.Tokens.default_, UsdGeom.Tokens.render, UsdGeom.Tokens.proxy, UsdGeom.Tokens.guide)
POINT_INSTANCER_LIGHTS = "lights in point-instancer prototypes are not supported; ignored"


@dataclass
class FaceSubset:
    """A materialBind face subset and the material it binds."""
    path: str
    prim: object
    owns_faces: bool      # no face is its own (all out of range, or an earlier subset's): no piece
    material: int = -1


@dataclass
class LoadedScene:
    scene: object
    resolution: tuple                 # (width, height)
    camera_path: str                  # '' when the camera was made up to frame the scene
    warnings: list = field(default_factory=list)
    # meshes, triangles, spheres, lights, instances, materials, prototypes
    counts: dict = field(default_factory=dict)
    light_kinds: dict = field(default_factory=dict)  # 'rect' -> how many, ...
    textures: dict = field(default_factory=dict)     # texture asset path -> resolved file, None if missing
    prims: int = 0                                   # prims on the stage
    # prims rendered with motion blur -> what moves ('transform', 'deformation'); empty when nothing moves
    moving: dict = field(default_factory=dict)
    shutter: object = None                           # motion.Shutter, or None (no motion blur)
    # The render settings' (aspectRatioConformPolicy, pixelAspectRatio) (renderer/camera_framing.h);
    # None without render settings: the renderer's defaults, which are the schema's
    framing: tuple = None


def matrix(gf_matrix):
    """Gf.Matrix4d -> the (4, 4) float64 row-vector array gi._core takes."""
    return np.array(gf_matrix, dtype=np.float64)


def pxr_error_message(error):
    """The last line of a Tf error without its "Error in 'function' at line N in file F :" prefix."""
    lines = [line.strip() for line in str(error).splitlines() if line.strip()]
    last = lines[-1] if lines else str(error)
    match = re.search(r" : '(.*)'$", last)
    return match.group(1) if match else last


# Composition errors that mean a layer or a prim the stage names could not be found.
MISSING_ERRORS = ("ErrorInvalidSublayerPath", "ErrorInvalidAssetPath", "ErrorUnresolvedPrimPath")


def missing_layers(stage):
    """What the stage's composition could not find (sublayers, references, payloads), as messages."""
    return [str(error).strip() for error in stage.GetCompositionErrors() if type(error).__name__ in MISSING_ERRORS]


def open_stage(path, allow_missing=False):
    """The stage at `path`; SceneError naming the file if it is missing or not USD, or if a sublayer,
    reference or payload it names cannot be found (unless allow_missing: then the stage renders
    without them, and missing_layers(stage) says what they are)."""
    path = str(path)
    if not os.path.exists(path):
        raise SceneError(f"{path}: no such file")
    if os.path.isdir(path):
        raise SceneError(f"{path}: is a directory, not a USD file")
    if not Usd.Stage.IsSupportedFile(path):
        raise SceneError(f"{path}: not a readable USD file (unknown file extension)")
    try:
        stage = Usd.Stage.Open(path)
    except Exception as error:  # Tf.ErrorException carrying the parser's message
        raise SceneError(f"{path}: not a readable USD file ({pxr_error_message(error)})") from None
    if stage is None:
        raise SceneError(f"{path}: not a readable USD file")
    missing = missing_layers(stage)
    if missing and not allow_missing:
        raise SceneError(f"{path}: {len(missing)} layer(s) or prim(s) it names cannot be found "
                         f"(--allow-missing renders without them): " + "; ".join(missing))
    return stage


class StageLoader(motion.MotionSampling):
    """One pass over a stage, adding what it finds to `scene`."""

    def __init__(self, stage, scene, time, file, refine_level=0, shutter=None, purposes=RENDERED_PURPOSES):
        self.stage, self.scene, self.time, self.file = stage, scene, time, file
        self.purposes = tuple(purposes)
        self.refine_level = refine_level
        self.shutter = shutter  # motion.Shutter: moving prims are sampled over it
        self.xforms = UsdGeom.XformCache(time)
        self.step_xforms = {}   # time -> XformCache, for the motion steps
        self.moving = {}        # prim path -> kinds of motion (motion.MotionSampling.note_motion)
        self.warnings = []
        self.materials = MaterialLibrary(scene, time, self.warn)
        self.prototypes = {}    # prototype root path -> prototype id
        self.counts = Counter(meshes=0, triangles=0, spheres=0, lights=0, instances=0, prototypes=0)
        self.light_kinds = Counter()

    def warn(self, prim_path, message):
        self.warnings.append(f"{self.file}: {prim_path}: {message}")

    def world(self, prim):
        return self.xforms.GetLocalToWorldTransform(prim)

    def is_rendered(self, prim):
        """Visible (inherited visibility) and of a purpose rendered (included_purposes)."""
        imageable = UsdGeom.Imageable(prim)
        if not imageable:
            return True
        if imageable.ComputeVisibility(self.time) == UsdGeom.Tokens.invisible:
            return False
        return imageable.ComputePurpose() in self.purposes

    # -- traversal -------------------------------------------------------------------------------
    def load(self):
        for error in self.stage.GetCompositionErrors():  # missing references, sublayers, ...
            self.warn(getattr(error.rootSite, "path", "/"), str(error).strip())
        prims = iter(Usd.PrimRange(self.stage.GetPseudoRoot()))
        for prim in prims:
            try:
                self.visit(prim, prims)
            except UNREADABLE as error:  # a malformed prim is left out, not the whole stage
                self.warn(str(prim.GetPath()), f"could not be read ({error_text(error)}); ignored with what is under it")
                prims.PruneChildren()

    def visit(self, prim, prims):
        if not self.is_rendered(prim):
            prims.PruneChildren()
        elif prim.IsInstance():
            self.add_instanceable(prim)
            prims.PruneChildren()
        elif prim.IsA(UsdGeom.PointInstancer):
            self.add_point_instancer(prim)
            prims.PruneChildren()
        else:
            self.add_prim(prim, matrix(self.world(prim)))

    def add_prim(self, prim, transform):
        """A gprim or a light; anything else is a container (or not renderable) and is passed over."""
        if prim.IsA(UsdGeom.Gprim):
            self.add_gprim(prim, transform)
        elif is_light(prim):
            self.add_light(prim, self.world(prim))

    # -- geometry --------------------------------------------------------------------------------
    def add_gprim(self, prim, transform, prototype=-1):
        name = str(prim.GetPath())
        if prim.HasAPI(UsdLux.MeshLightAPI):
            self.warn(name, "mesh lights (MeshLightAPI) are not supported; rendered as plain geometry "
                            "(an emissive UsdPreviewSurface emits)")
        if prim.IsA(UsdGeom.Sphere):
            self.add_sphere(prim, transform, prototype)
        elif prim.IsA(UsdGeom.Mesh) or prim.GetTypeName() in IMPLICIT_TYPES:
            self.add_triangles(prim, transform, prototype)
        else:
            self.warn(name, f"{prim.GetTypeName()} geometry is not supported; ignored")

    def add_sphere(self, prim, transform, prototype):
        material, _ = self.materials.bind(prim)
        radius_attribute = UsdGeom.Sphere(prim).GetRadiusAttr()
        radius = float(radius_attribute.Get(self.time))
        name = str(prim.GetPath())
        steps = None
        times = self.motion_times(prim, [radius_attribute]) if prototype < 0 else None
        if times and radius > 0:
            # A changing radius is a scale of the unit of the sphere's own space (row vectors: scale first).
            scales = [Gf.Matrix4d().SetScale(float(radius_attribute.Get(t)) / radius) for t in times]
            steps = np.stack([matrix(scale * self.world_at(prim, t)) for scale, t in zip(scales, times)])
            steps = steps if motion.moving(steps) else None
        if self.scene.add_sphere(name, (0.0, 0.0, 0.0), radius, material, transform, prototype,
                                 motion_transforms=steps) >= 0:
            self.counts["spheres"] += 1
            if steps is not None:
                self.note_motion(prim, "transform")

    def add_triangles(self, prim, transform, prototype):
        """A mesh, or a tessellated cube / cylinder / cone / capsule / plane. A mesh's materialBind
        GeomSubsets become pieces of their own with their own materials (as Hydra splits them)."""
        name = str(prim.GetPath())
        material, uv_names = self.materials.bind(prim)
        warn = lambda message: self.warn(name, message)  # noqa: E731  (binds the prim's name)
        subsets = []
        if prim.IsA(UsdGeom.Mesh):
            mesh = UsdGeom.Mesh(prim)
            subsets, piece_of_face = self.material_subsets(mesh)
            subsets, uv_names = self.subset_materials(subsets, material, uv_names)
            pieces = mesh_triangles(mesh, self.time, warn, uv_names, self.refine_level, piece_of_face,
                                    len(subsets) + 1)
        else:
            triangles = implicit_triangles(prim, self.time, warn)
            pieces = None if triangles is None else [triangles]
        if pieces is None:
            return
        double_sided = bool(UsdGeom.Gprim(prim).GetDoubleSidedAttr().Get(self.time))
        deform_times, transform_steps = self.mesh_motion(prim, prototype)
        # A deforming mesh: the same topology at each step's points, so its tessellation (refinement
        # included) at each step time gives each piece's vertices there, in the same order.
        step_pieces = None
        if deform_times is not None:
            quiet = lambda message: None  # noqa: E731  (warned once, at the render time, above)
            step_pieces = [mesh_triangles(mesh, t, quiet, uv_names, self.refine_level, piece_of_face, len(subsets) + 1)
                           for t in deform_times]
        added, deformed = 0, False
        # The faces in no subset under the mesh's name and material, then each subset's faces under
        # its own path and material (as Hydra splits them).
        names = [(name, material)] + [(subset.path, subset.material) for subset in subsets]
        for index, ((piece_name, piece_material), piece) in enumerate(zip(names, pieces)):
            if piece is None:
                continue
            piece_points = None
            if step_pieces is not None:
                steps = [None if s is None or s[index] is None else s[index].positions for s in step_pieces]
                if all(p is not None and p.shape == piece.positions.shape for p in steps):
                    piece_points = np.ascontiguousarray(np.stack(steps), np.float32)
                    deformed = True
                else:
                    warn("its tessellation changes during the shutter; rendered without deformation blur")
            mesh_id = self.scene.add_mesh(piece_name, piece.positions, piece.indices, piece.normals,
                                          piece.uvs, piece_material, transform, double_sided, prototype,
                                          motion_points=piece_points, motion_transforms=transform_steps)
            if mesh_id >= 0:
                added += 1
                self.counts["triangles"] += len(piece.indices)
        if added:
            self.counts["meshes"] += 1  # a mesh prim, however many pieces its subsets made
            if transform_steps is not None:
                self.note_motion(prim, "transform")
            if deformed:
                self.note_motion(prim, "deformation")

    def material_subsets(self, mesh):
        """The mesh's materialBind face subsets (authored order) and which of them owns each face
        (piece_of_face, as gi._core.assign_subset_faces decides it for both hosts: valid indices
        only, a face claimed by several going to the first, with warnings naming the subset).
        Subsets that are not face sets or cannot be read are left out here, with a warning."""
        binding = UsdShade.MaterialBindingAPI(mesh.GetPrim())
        subsets = binding.GetMaterialBindSubsets()
        if not subsets:
            return [], None
        face_sets = []
        for subset in subsets:
            path = str(subset.GetPath())
            element_type = subset.GetElementTypeAttr().Get(self.time)
            if element_type != UsdGeom.Tokens.face:
                self.warn(path, f"materialBind subset of element type '{element_type}' is not a face set; ignored")
                continue
            try:
                indices = np.asarray(subset.GetIndicesAttr().Get(self.time) or [], np.int64).reshape(-1)
            except UNREADABLE as error:
                self.warn(path, f"indices could not be read ({error_text(error)}); subset ignored")
                continue
            face_sets.append((subset, np.ascontiguousarray(np.clip(indices, -1, 2 ** 31 - 1), np.int32)))
        try:
            from ._core import assign_subset_faces
        except ImportError:  # no compiled renderer (gi inspect): meshes are counted, not cut
            return [], None
        if not face_sets:
            return [], None
        face_count = len(mesh.GetFaceVertexCountsAttr().Get(self.time) or [])
        assigned = assign_subset_faces(face_count, [(str(s.GetPath()), indices) for s, indices in face_sets],
                                       str(binding.GetMaterialBindSubsetsFamilyType()), str(mesh.GetPath()))
        for subject, message in assigned["warnings"]:
            self.warn(subject, message)
        out = [FaceSubset(str(s.GetPath()), s.GetPrim(), owns) for (s, _), owns in zip(face_sets, assigned["owns_faces"])]
        return out, assigned["piece_of_face"]

    def subset_materials(self, subsets, mesh_material, uv_names):
        """Binds each subset's material (resolved on the subset prim as on any gprim: its own binding,
        else the mesh's); a subset with no usable material keeps the mesh's. Returns the subsets and
        the uv primvar names every piece's material reads (the mesh's first)."""
        names = list(uv_names)
        for subset in subsets:
            if not subset.owns_faces:
                continue
            subset.material, subset_uv_names = self.materials.bind(subset.prim, display_color=False)
            if subset.material < 0:
                subset.material = mesh_material
            names += [n for n in subset_uv_names if n not in names]
        return subsets, tuple(names)

    # -- instancing ------------------------------------------------------------------------------
    def prototype_for(self, root, holds_lights_warning=""):
        """The prototype holding `root`'s geometry (relative to root), added on first use only.
        Lights inside are skipped, with `holds_lights_warning` if given."""
        key = str(root.GetPath())
        if key in self.prototypes:
            return self.prototypes[key]
        prototype = self.scene.add_prototype(key)
        self.prototypes[key] = prototype
        self.counts["prototypes"] += 1
        to_root = self.world(root).GetInverse()
        # Instance proxies: instanceable prims nested in a prototype are flattened into it.
        prims = iter(Usd.PrimRange(root, Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)))
        for prim in prims:
            if not self.is_rendered(prim):
                prims.PruneChildren()
            elif prim.IsA(UsdGeom.PointInstancer):
                self.warn(prim.GetPath(), "point instancers inside prototypes are not supported; ignored")
                prims.PruneChildren()
            elif prim.IsA(UsdGeom.Gprim):
                self.add_gprim(prim, matrix(self.world(prim) * to_root), prototype)
            elif is_light(prim) and holds_lights_warning:
                self.warn(prim.GetPath(), holds_lights_warning)
        return prototype

    def add_instance(self, prototype, transform, name, steps=None, prim=None):
        if self.scene.add_instance(prototype, matrix(transform), name, motion_transforms=steps) >= 0:
            self.counts["instances"] += 1
            if steps is not None and prim is not None:
                self.note_motion(prim, "transform")

    def add_instanceable(self, prim):
        """An instanceable prim: its prototype's geometry once, then one instance of it here."""
        self.add_instance(self.prototype_for(prim.GetPrototype()), self.world(prim), str(prim.GetPath()),
                          self.transform_steps(prim, self.motion_times(prim)), prim)
        self.add_lights_inside(prim)

    def add_lights_inside(self, instance):
        """Lights are not instanced: add those inside an instanceable prim at their world place."""
        prims = iter(Usd.PrimRange(instance, Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)))
        for prim in prims:
            if not self.is_rendered(prim):
                prims.PruneChildren()
            elif is_light(prim) and not prim.IsA(UsdGeom.Gprim):
                self.add_light(prim, self.world(prim))

    def add_point_instancer(self, prim):
        instancer = UsdGeom.PointInstancer(prim)
        path = str(prim.GetPath())
        roots = [self.stage.GetPrimAtPath(target) for target in instancer.GetPrototypesRel().GetTargets()]
        proto_indices = instancer.GetProtoIndicesAttr().Get(self.time) or []
        # ExcludeProtoXform: pxr computes nothing at all if one protoIndex is bad, so the prototype
        # roots' own transforms are applied below. IgnoreMask keeps instance i at index i.
        local = instancer.ComputeInstanceTransformsAtTime(
            self.time, self.time, UsdGeom.PointInstancer.ExcludeProtoXform, UsdGeom.PointInstancer.IgnoreMask)
        if len(local) != len(proto_indices):
            self.warn(path, f"{len(proto_indices)} protoIndices but {len(local)} instance transforms "
                            f"(positions/orientations/scales disagree); instancer ignored")
            return
        shown = instancer.ComputeMaskAtTime(self.time) or [True] * len(proto_indices)  # invisible/inactive ids
        instancer_world = self.world(prim)
        step_local, step_worlds = self.instancer_motion(instancer, len(local))
        for i, (index, transform) in enumerate(zip(proto_indices, local)):
            if not shown[i]:
                continue
            if not 0 <= index < len(roots) or not roots[index]:
                self.warn(path, f"instance {i} uses prototype {index}, which does not exist; skipped")
                continue
            root = roots[index]
            root_local, _ = self.xforms.GetLocalTransformation(root)
            prototype = self.prototype_for(root, POINT_INSTANCER_LIGHTS)
            steps = None
            if step_local is not None:
                steps = np.stack([matrix(root_local * step[i] * world) for step, world in zip(step_local, step_worlds)])
                steps = steps if motion.moving(steps) else None
            # Named as hdGi names Hydra's instances (Scene::indexedName): emissive instances sort by point.
            self.add_instance(prototype, root_local * transform * instancer_world,
                              descriptors.indexed_name(path, i, len(proto_indices)), steps, prim)

    # -- lights ----------------------------------------------------------------------------------
    def add_light(self, prim, world):
        desc = light_desc(prim, world, self.time, self.warn)
        if desc is None:
            return
        # Its world transform at the motion steps over the shutter, as a moving mesh's (the
        # renderer blurs area lights and warns about the others).
        steps = self.transform_steps(prim, self.motion_times(prim))
        if steps is not None:
            desc.motion_transforms = np.ascontiguousarray(steps)
            self.note_motion(prim, "transform")
        if self.scene.add_light(desc) >= 0:
            self.counts["lights"] += 1
            self.light_kinds[desc.kind] += 1


# -- camera and render settings ------------------------------------------------------------------

def render_settings(stage):
    """The stage's renderSettingsPrimPath prim, else the first RenderSettings prim, else None."""
    path = stage.GetMetadata("renderSettingsPrimPath")
    if path:
        prim = stage.GetPrimAtPath(path)
        if prim and prim.IsA(UsdRender.Settings):
            return UsdRender.Settings(prim)
    for prim in stage.Traverse():
        if prim.IsA(UsdRender.Settings):
            return UsdRender.Settings(prim)
    return None


def settings_resolution(settings, time):
    if settings is None:
        return DEFAULT_RESOLUTION
    resolution = settings.GetResolutionAttr().Get(time)
    return (int(resolution[0]), int(resolution[1])) if resolution is not None else DEFAULT_RESOLUTION


def image_framing(schema, time, inherited, warn):
    """(aspectRatioConformPolicy, pixelAspectRatio) of a UsdRender settings or product prim: what
    it authors, else `inherited` (a product inherits its settings'), else the schema's fallbacks.
    A token the schema does not allow, or a pixel aspect ratio that is not a positive number,
    warns naming the prim, and the value it would otherwise have is used."""
    policy_attr, aspect_attr = schema.GetAspectRatioConformPolicyAttr(), schema.GetPixelAspectRatioAttr()
    if inherited is None:
        definition = Usd.SchemaRegistry().FindConcretePrimDefinition(schema.GetPrim().GetTypeName())
        inherited = (str(definition.GetAttributeFallbackValue(policy_attr.GetName())),
                     float(definition.GetAttributeFallbackValue(aspect_attr.GetName())))
    policy, aspect = inherited
    where = str(schema.GetPath())
    if policy_attr.HasAuthoredValue():
        token = str(policy_attr.Get(time))
        if token in policy_attr.GetMetadata("allowedTokens"):
            policy = token
        else:
            warn(where, f"aspectRatioConformPolicy '{token}' is unknown; {policy} is used")
    if aspect_attr.HasAuthoredValue():
        value = float(aspect_attr.Get(time))
        if math.isfinite(value) and value > 0:
            aspect = value
        else:
            warn(where, f"pixelAspectRatio {value:g} is not a positive number; {aspect:g} is used")
    return policy, aspect


def relationship_targets(relationship, warn):
    """A relationship's forwarded targets; [] with a warning naming it when the stage authors
    something pxr cannot compose as one under its name (an attribute of that name)."""
    try:
        return list(relationship.GetForwardedTargets())
    except UNREADABLE as error:
        warn(str(relationship.GetPath()), f"could not be read as a relationship ({error_text(error)}); ignored")
        return []


def camera_prim(stage, settings, requested, file, warn):
    """The `requested` camera path, else the render settings' camera, else the first camera, else None."""
    if requested:
        prim = stage.GetPrimAtPath(requested) if requested.startswith("/") else None
        if not prim or not prim.IsA(UsdGeom.Camera):
            raise SceneError(f"{file}: {requested} is not a camera prim")
        return prim
    if settings is not None:
        for target in relationship_targets(settings.GetCameraRel(), warn):
            prim = stage.GetPrimAtPath(target)
            if prim and prim.IsA(UsdGeom.Camera):
                return prim
    return next((prim for prim in stage.Traverse() if prim.IsA(UsdGeom.Camera)), None)


def camera_desc(prim, world, time):
    camera = UsdGeom.Camera(prim)
    desc = descriptors.CameraDesc()
    desc.name = str(prim.GetPath())
    desc.projection = str(camera.GetProjectionAttr().Get(time))
    desc.focal_length = float(camera.GetFocalLengthAttr().Get(time))
    desc.horizontal_aperture = float(camera.GetHorizontalApertureAttr().Get(time))
    desc.vertical_aperture = float(camera.GetVerticalApertureAttr().Get(time))
    desc.horizontal_aperture_offset = float(camera.GetHorizontalApertureOffsetAttr().Get(time))
    desc.vertical_aperture_offset = float(camera.GetVerticalApertureOffsetAttr().Get(time))
    desc.f_stop = float(camera.GetFStopAttr().Get(time))
    desc.focus_distance = float(camera.GetFocusDistanceAttr().Get(time))
    near, far = camera.GetClippingRangeAttr().Get(time)
    desc.clipping_range = (float(near), float(far))
    # As authored: the renderer warns, naming the camera, when close < open.
    desc.shutter_open = float(camera.GetShutterOpenAttr().Get(time))
    desc.shutter_close = float(camera.GetShutterCloseAttr().Get(time))
    desc.transform = matrix(world)
    return desc


def included_purposes(settings, requested, warn):
    """The purposes rendered, `default` always among them: `requested` (gi render --purposes, the
    extra purposes as usdrecord's flag names them), else the render settings' includedPurposes, else
    default and render (that attribute's fallback). An unknown purpose warns and is left out."""
    where = "--purposes"
    if requested is None and settings is not None:
        attribute = settings.GetIncludedPurposesAttr()
        if attribute.HasAuthoredValue():
            try:
                requested, where = list(attribute.Get() or []), str(settings.GetPath())
            except UNREADABLE as error:
                warn(str(settings.GetPath()), f"includedPurposes could not be read ({error_text(error)}); "
                                              f"rendering the default and render purposes")
    if requested is None:
        return RENDERED_PURPOSES
    purposes = [UsdGeom.Tokens.default_]
    for purpose in requested:
        if purpose not in PURPOSES:
            warn(where, f"unknown purpose {purpose!r} (known: {', '.join(PURPOSES)}); ignored")
        elif purpose not in purposes:
            purposes.append(purpose)
    return tuple(purposes)


def framing_camera(stage, time, purposes=RENDERED_PURPOSES):
    """The camera that frames a stage with no camera of its own: usdrecord's (gi._core.framing_camera,
    renderer/camera_framing.h), on the bounding box of what `gi` renders, measured as usdrecord
    measures it (UsdGeomBBoxCache with extents hints, its centroid and aligned size), and the stage's
    up axis. Without the compiled core nothing renders, so a stand-in is returned."""
    cache = UsdGeom.BBoxCache(time, list(purposes), useExtentsHint=True)
    try:
        box = cache.ComputeWorldBound(stage.GetPseudoRoot())
        center, size = box.ComputeCentroid(), box.ComputeAlignedRange().GetSize()
    except UNREADABLE:  # a malformed transform or extent somewhere: frame the origin
        center = size = (0.0, 0.0, 0.0)
    if not descriptors.HAVE_CORE:
        return descriptors.CameraDesc()
    from ._core import framing_camera as core_framing_camera
    z_up = UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
    return core_framing_camera(tuple(center), tuple(size), z_up)


def as_time_code(time):
    """A frame number as a time code; None: the earliest time, as usdrecord renders without
    frames (an attribute authored only as time samples has its first sample there, where at the
    default time it would have no value)."""
    if time is None:
        return Usd.TimeCode.EarliestTime()
    return time if isinstance(time, Usd.TimeCode) else Usd.TimeCode(float(time))


def camera_at(stage, camera_path, time):
    """The CameraDesc of the camera prim `camera_path` at `time` (a frame of a camera move)."""
    prim = stage.GetPrimAtPath(camera_path)
    time = as_time_code(time)
    desc = camera_desc(prim, UsdGeom.XformCache(time).GetLocalToWorldTransform(prim), time)
    shutter = motion.camera_shutter(prim, render_settings(stage), time, motion.frame_time(stage, time))
    desc.motion_transforms = motion.camera_transforms(prim, shutter)
    return desc


def load_stage(path, scene=None, camera=None, time=None, stage=None, allow_missing=False,
               refine_level=0, purposes=None) -> LoadedScene:
    """Loads the USD file `path` into `scene` (a new gi._core.Scene if None).

    camera: a camera prim path overriding the render settings' camera.
    time: a time code or frame number (default: the earliest time, see as_time_code).
    stage: the stage of `path` when it is open already (each frame of a sequence reads it).
    allow_missing: render a stage whose sublayers, references or payloads cannot all be found (each
    is a warning) instead of raising SceneError naming them.
    refine_level: how many times subdivision meshes are refined (0: their control cage; see
    render.COMPLEXITY_REFINE_LEVELS).
    purposes: the purposes rendered besides default (None: the render settings' includedPurposes,
    else render; see included_purposes).
    Raises SceneError naming the file when it is missing or not USD."""
    file = str(path)
    stage = stage if stage is not None else open_stage(file, allow_missing)
    scene = scene if scene is not None else descriptors.new_scene()
    time = as_time_code(time)
    settings = render_settings(stage)
    early_warnings = []  # before the loader exists to hold them
    prim = camera_prim(stage, settings, camera, file,
                       lambda where, message: early_warnings.append(f"{file}: {where}: {message}"))
    shutter = None
    if prim is not None:
        try:
            shutter = motion.camera_shutter(prim, settings, time, motion.frame_time(stage, time))
        except UNREADABLE:  # reported with the rest of the camera below
            pass
    purposes = included_purposes(settings, purposes, lambda where, message: early_warnings.append(
        f"{file}: {where}: {message}"))
    loader = StageLoader(stage, scene, time, file, refine_level, shutter, purposes)
    loader.warnings += early_warnings
    for message in missing_layers(stage):
        loader.warn("/", f"not found, rendered without it: {message}")
    loader.load()

    try:
        resolution = settings_resolution(settings, time)
    except UNREADABLE as error:
        loader.warn(str(settings.GetPath()), f"resolution could not be read ({error_text(error)}); "
                                             f"using {DEFAULT_RESOLUTION}")
        resolution = DEFAULT_RESOLUTION
    framing = None
    if settings is not None:
        try:
            framing = image_framing(settings, time, None, loader.warn)
        except UNREADABLE as error:
            loader.warn(str(settings.GetPath()), f"aspectRatioConformPolicy or pixelAspectRatio could not be read "
                                                 f"({error_text(error)}); the schema's fallbacks are used")
    desc = None
    if prim is not None:
        try:
            desc = camera_desc(prim, loader.world(prim), time)
        except UNREADABLE as error:
            loader.warn(str(prim.GetPath()), f"camera could not be read ({error_text(error)}); using one that "
                                             f"frames the whole scene")
    if desc is not None:
        desc.motion_transforms = motion.camera_transforms(prim, shutter)
        if desc.motion_transforms is not None:
            loader.note_motion(prim, "transform")
        scene.set_camera(desc)
        camera_path = str(prim.GetPath())
    else:
        if prim is None:
            loader.warn("/", "no camera in the stage; using one that frames the whole scene, as usdrecord does")
        scene.set_camera(framing_camera(stage, time, purposes))
        camera_path = ""

    counts = dict(loader.counts, materials=loader.materials.added)
    return LoadedScene(scene, resolution, camera_path, loader.warnings, counts, dict(loader.light_kinds),
                       dict(loader.materials.textures), sum(1 for _ in stage.TraverseAll()), loader.moving, shutter,
                       framing)
